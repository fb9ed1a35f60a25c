"""The photo appearance's road fill along the vanishing point's rays (:mod:`sdn3d.editing.photo.road`,
``fill='rays'``) and the removal of a car's shadow with it."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.editing.apply import Delete, apply_edits
from sdn3d.editing.photo.fill import fill_hole, inpaint
from sdn3d.editing.photo.road import ray_fill, shadowed_road, vanishing_point
from sdn3d.editing.photo.settings import FILL, PhotoSettings, PhotoSettingsError
from sdn3d.editing.photo.transfer import render_photo

pytestmark = pytest.mark.usefixtures("one_torch_thread")

K = torch.tensor([[100.0, 0.0, 63.5], [0.0, 100.0, 20.0], [0.0, 0.0, 1.0]], dtype=torch.float64)


def _lanes(height: int = 64, width: int = 128,
           vp: tuple[float, float] = (63.5, 20.0)) -> tuple[torch.Tensor, torch.Tensor]:
    """``(image, line)``: grey road below the vanishing point's row with three white lines converging on it, sky
    above; ``line`` marks the line pixels."""
    ys, xs = torch.meshgrid(torch.arange(height, dtype=torch.float32), torch.arange(width, dtype=torch.float32),
                            indexing="ij")
    below = ys > vp[1] + 2
    line = torch.zeros(height, width, dtype=torch.bool)
    for slope in (-1.6, 0.0, 1.6):  # x - vp_x = slope * (y - vp_y)
        line |= below & ((xs - vp[0] - slope * (ys - vp[1])).abs() <= 1.5 + 0.05 * (ys - vp[1]))
    image = torch.stack([torch.full((height, width), 0.4), torch.full((height, width), 0.4),
                         torch.full((height, width), 0.42)])
    image[:, ~below] = torch.tensor([0.6, 0.75, 0.9])[:, None]
    image[:, line] = 0.95
    return image, line


def test_vanishing_point_follows_the_cars_axis_and_falls_back_to_the_camera_forward():
    assert vanishing_point(K) == pytest.approx((63.5, 20.0))
    # a car heading straight down the road (ry = -90 degrees: its axis is the camera's z) and one driving towards us
    assert vanishing_point(K, -math.pi / 2) == pytest.approx((63.5, 20.0))
    assert vanishing_point(K, math.pi / 2) == pytest.approx((63.5, 20.0))
    u, v = vanishing_point(K, -math.pi / 2 + 0.3)  # turned 0.3 rad: the road's point moves sideways, not up
    assert u == pytest.approx(63.5 + 100 * math.tan(0.3)) and v == pytest.approx(20.0)
    assert vanishing_point(K, 0.0) == pytest.approx((63.5, 20.0))  # a car across the road: the camera's forward


def test_rays_carry_lane_lines_through_a_hole_where_telea_smears_them():
    image, line = _lanes()
    hole = torch.zeros_like(line)
    hole[34:52, 40:90] = True
    filled, reached = ray_fill(image, hole, (63.5, 20.0), texture=0.0)
    assert bool(reached[hole].all())
    on, off = hole & line, hole & ~_grow(line, 2)
    assert float(filled[:, on].mean()) > 0.8 and float(filled[:, off].mean()) < 0.45
    error = float((filled - image).abs()[:, hole].mean())
    telea = inpaint(image, hole, "telea")
    assert float(telea[:, on].mean()) < 0.75  # the plain fill loses the lines (what rays are for)
    assert error < 0.04 and error < 0.6 * float((telea - image).abs()[:, hole].mean())
    assert torch.equal(filled[:, ~hole], image[:, ~hole])


def test_rays_skip_other_objects_and_stop_at_the_vanishing_point():
    image, line = _lanes()
    hole = torch.zeros_like(line)
    hole[30:40, 70:80] = True
    other = torch.zeros_like(line)
    other[26:30, 60:90] = True  # a car farther along the road, between the hole and the vanishing point
    image[:, other] = torch.tensor([0.9, 0.1, 0.1])[:, None]
    filled, _ = ray_fill(image, hole, (63.5, 20.0), keep_out=other, texture=0.0)
    red = filled[0, hole] - filled[1, hole]
    assert float(red.abs().max()) < 0.05  # no red carried in from the other car
    alone, _ = ray_fill(image, hole, (63.5, 20.0), texture=0.0)
    assert float((alone[0, hole] - alone[1, hole]).max()) > 0.2  # without keep_out it would be


def test_rays_texture_puts_the_roads_grain_back():
    gen = torch.Generator().manual_seed(0)
    image, line = _lanes()
    image = (image + 0.05 * torch.randn(image.shape, generator=gen)).clamp(0, 1)
    hole = torch.zeros_like(line)
    hole[40:56, 10:30] = True
    flat, _ = ray_fill(image, hole, (63.5, 20.0), texture=0.0)
    grain, _ = ray_fill(image, hole, (63.5, 20.0), texture=1.0)

    def lap(x: torch.Tensor) -> float:  # mean absolute Laplacian on the hole, away from the lines
        g = x.mean(0)
        lp = (4 * g[1:-1, 1:-1] - g[:-2, 1:-1] - g[2:, 1:-1] - g[1:-1, :-2] - g[1:-1, 2:]).abs()
        return float(lp[hole[1:-1, 1:-1] & ~_grow(line, 2)[1:-1, 1:-1]].mean())

    assert lap(flat) < 0.5 * lap(image)  # smooth along the rays alone
    assert 0.7 * lap(image) < lap(grain) < 1.4 * lap(image)  # the grain comes back, about as strong


def test_shadowed_road_is_darker_than_the_road_on_its_own_row_despite_fog():
    h, w = 40, 60
    rows = torch.linspace(0.8, 0.4, h)[:, None].expand(h, w)  # fog: far rows (top) lighter
    image = torch.stack([rows, rows, rows * 1.02])
    image[:, 25:32, 20:40] *= 0.55  # a shadow on the near road
    from sdn3d.editing.photo.recolor import srgb_to_lab

    road = srgb_to_lab(torch.tensor([[0.6, 0.6, 0.612]]))[0]
    everywhere = torch.ones(h, w, dtype=torch.bool)
    lit = everywhere.clone()
    lit[25:32, 20:40] = False
    dark = shadowed_road(image, road, everywhere, lit)
    assert bool(dark[25:32, 20:40].all()) and int(dark.sum()) == 7 * 20  # the shadow alone, no foggy row


def test_fill_hole_rays_falls_back_to_telea_where_no_ray_reaches():
    image = torch.full((3, 30, 40), 0.5)
    hole = torch.zeros(30, 40, dtype=torch.bool)
    hole[10:20, 10:30] = True
    out = fill_hole(image, hole, PhotoSettings(fill="rays"), keep_out=~hole)  # no source at all: Telea
    assert float((out - 0.5).abs()[:, hole].max()) < 0.02


def test_ray_settings_are_checked():
    assert PhotoSettings(fill="rays").fill == "rays"
    for bad in ({"shadow_mode": "paint"}, {"ray_span": 0}, {"ray_texture": 3.0}, {"shadow_light": 0.1}):
        with pytest.raises(PhotoSettingsError):
            PhotoSettings(**bad)


def test_delete_with_rays_removes_the_cars_shadow(monkeypatch):
    """delete_effects + rays: the removed car's cast shadow on the road (halved grey) is filled from lit road, and
    the vacated footprint is refilled."""
    from tests.test_photo import FRAME, _scene
    from tests.test_photo_parts import BEHIND, _lit_with_shadow

    scene = _scene([BEHIND])
    image, _ = _lit_with_shadow(monkeypatch, scene)
    shadow = (image[0] < 0.3) & (image[0] - image[2]).abs().lt(1e-6)
    edited = apply_edits(scene, [Delete(12001)])
    settings = PhotoSettings(fill="rays", delete_effects=True, relight=False, contact_shadow=0.0)
    result = render_photo(image, FRAME, scene, edited, settings=settings)
    assert float(result.image[:, shadow].mean()) > 0.8 * float(image[:, ~shadow & (result.source == 0)].mean())
    assert float((result.source[shadow] == FILL).float().mean()) > 0.5  # filled with the hole, and marked so
    kept = PhotoSettings(fill="rays", delete_effects=True, delete_shadow=False, relight=False, contact_shadow=0.0)
    plain = render_photo(image, FRAME, scene, edited, settings=kept)
    outside = shadow & (plain.source != FILL)
    assert bool(outside.any()) and torch.equal(plain.image[:, outside], image[:, outside])


def _grow(mask: torch.Tensor, r: int) -> torch.Tensor:
    return torch.nn.functional.max_pool2d(mask.float()[None, None], 2 * r + 1, 1, r)[0, 0] > 0
