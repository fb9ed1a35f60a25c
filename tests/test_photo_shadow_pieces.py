"""A removed car's shadow that runs on past the hole outside the region its fitted box gives (issue 41, session 21:
the real frame's red car left its shadow's dark tip beside its rear wheel): :func:`~sdn3d.editing.photo.fill.
shadow_pieces` and the delete's fill with ``photo.shadow_mode='fill'``."""

from __future__ import annotations

import pytest
import torch

from sdn3d.editing.photo.fill import shadow_pieces
from sdn3d.editing.photo.settings import PhotoSettings, PhotoSettingsError

pytestmark = pytest.mark.usefixtures("one_torch_thread")


def _hole_and_shade() -> tuple[torch.Tensor, torch.Tensor, dict[str, torch.Tensor]]:
    """``(hole (96, 160), dark (96, 160), pieces)``: a hole (rows 20-69, columns 40-99: 50 rows, a reach of 5 pixels
    at 0.1) whose lower rows 55-69 are the car's shadow (dark); outside it, dark pieces: the shadow's tip left of it
    (rows 60-66, columns 36-39, touching the hole's shadow), a tree's shadow from the hole's shadow out to the picture's
    right edge (rows 64-67), a dark patch beside a lit edge of the hole (rows 45-49, columns 100-102: the hole there
    is lit), a dark piece touching the hole's shadow but above its lower half (rows 40-44, columns 36-39, joined to
    the shadow's rows by nothing) and a far one (rows 56-58, columns 20-24)."""
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[20:70, 40:100] = True
    dark = torch.zeros_like(hole)
    dark[55:70, 40:100] = True
    pieces = {name: torch.zeros_like(hole) for name in ("tip", "tree", "lit_edge", "high", "far")}
    pieces["tip"][60:67, 36:40] = True
    pieces["tree"][64:68, 100:160] = True
    pieces["lit_edge"][45:50, 100:103] = True
    pieces["high"][40:45, 36:40] = True
    pieces["far"][56:59, 20:25] = True
    for piece in pieces.values():
        dark |= piece
    return hole, dark, pieces


def test_the_shadow_running_on_past_the_hole_joins_it_and_nothing_else():
    hole, dark, pieces = _hole_and_shade()
    found = shadow_pieces(dark, hole, 0.1, 0.5)
    assert torch.equal(found, pieces["tip"])
    assert not bool(shadow_pieces(dark, hole, 0.0, 0.5).any())


def test_a_shadow_piece_past_the_reach_or_above_the_ground_rows_stays():
    hole, dark, pieces = _hole_and_shade()
    # The tip reaches 4 pixels out: with a reach of 3 (0.06 of 50 rows) it runs on beyond it.
    assert not bool(shadow_pieces(dark, hole, 0.06, 0.5).any())
    # Ground rows from the hole's top row on: the dark piece beside the hole's upper half is shadow too, if it
    # touches the hole's shadow; it does not here (rows 40-44 against the shadow's 55-69), so it still stays.
    assert torch.equal(shadow_pieces(dark, hole, 0.1, 0.0), pieces["tip"])
    joined = dark.clone()
    joined[40:70, 36:40] = True  # the high piece joined down to the tip: one piece reaching above the ground rows
    assert not bool(shadow_pieces(joined, hole, 0.1, 0.5).any())
    whole = torch.zeros_like(hole)
    whole[40:70, 36:40] = True
    assert torch.equal(shadow_pieces(joined, hole, 0.1, 0.0), whole)  # counted from the top row: all of it


def test_a_delete_fills_the_shadow_tip_its_box_region_missed():
    """The delete's rays fill with the removed car's shadow: the search region (from its fitted box) lies below the
    car and misses the shadow's tip left of it; with ``shadow_reach`` (default) the tip is filled with lit road after
    the hole, whose fill stays as it was, with 0 (the behaviour before) it stays dark."""
    import sdn3d.editing.photo.transfer as transfer
    from sdn3d.editing.photo.road import road_colours

    gen = torch.Generator().manual_seed(0)
    image = 0.5 + 0.01 * torch.randn(3, 96, 160, generator=gen)
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[20:70, 40:100] = True
    image[:, 55:70, 40:100] = 0.2  # the car's shadow under it, in the hole
    tip = torch.zeros_like(hole)
    tip[60:67, 35:40] = True
    image[:, tip] = 0.2
    search = torch.zeros_like(hole)
    search[72:90, 50:110] = True  # the box's region: below the car, off it
    ring = ~torch.nn.functional.max_pool2d((hole | search).float()[None, None], 13, 1, 6)[0, 0].bool()
    road = road_colours(image, ring)
    objects = torch.zeros_like(hole)
    vp = (80.0, -2000.0)
    before, matte_before = transfer._rays_with_effects(image, hole, objects, search, ring, road,
                                                       PhotoSettings(fill="rays", shadow_reach=0.0), vp)
    assert float(before[:, tip].mean()) < 0.25  # the tip stays
    assert not bool((matte_before[tip] < 0).any())
    after, matte = transfer._rays_with_effects(image, hole, objects, search, ring, road, PhotoSettings(fill="rays"), vp)
    assert bool((matte[tip] < 0).all())  # filled (render_photo marks these pixels fill)
    assert abs(float(after[:, tip].mean()) - 0.5) < 0.05  # lit road where the tip was
    assert torch.equal(after[:, hole], before[:, hole])  # the hole's own fill stays as it was (the tip: Telea after)
    # nothing outside the hole and the tip changed
    assert torch.equal(after[:, ~hole & ~tip], image[:, ~hole & ~tip])


def test_shadow_reach_is_checked_by_name():
    assert PhotoSettings().shadow_reach == 0.1
    with pytest.raises(PhotoSettingsError, match="shadow_reach"):
        PhotoSettings(shadow_reach=-0.1)
    with pytest.raises(PhotoSettingsError, match="shadow_reach"):
        PhotoSettings(shadow_reach=0.9)
