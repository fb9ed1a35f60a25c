"""The photo appearance's vehicle parts (issue 41 item 2): unseen surfaces drawn part by part from the car's own
pixels, a per-pixel part map, recolour of the body part only; and the removal-with-effects option (item 3)."""

from __future__ import annotations

import math

import pytest
import torch

from sdn3d.editing.apply import apply_edits
from sdn3d.editing.ops import Delete, Rotate
from sdn3d.editing.photo.recolor import recolor_pixels
from sdn3d.editing.photo.settings import (
    DEFAULT,
    FALLBACK,
    FLAT_CODES,
    PART,
    PART_DEFAULTS,
    SOURCE_NAMES,
    PhotoSettings,
    PhotoSettingsError,
    part_picture,
)
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.meshes.parts import Part
from sdn3d.scene.code import SceneObject
from tests.test_photo import FRAME, INPUT_SIZE, _k_input, _scene, _surface_colors

pytestmark = pytest.mark.usefixtures("one_torch_thread")
BEHIND = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=-math.pi / 2, location=(-2.0, 1.6, 12.0))
PARTS = PhotoSettings(relight=False, contact_shadow=0.0, fill="telea")


def test_settings_name_the_new_modes():
    assert PhotoSettings().unseen == "parts" and PhotoSettings().recolor_parts
    # off: on the seed-33 tuning tree (clone + fog, 16 deletes) it lost 1.2 dB to the auto fill on vacated region +
    # shadow band, although it won on the seed-31 tree's 9 deletes (docs/results/2026-11-28_cpu/issue41/)
    assert not PhotoSettings().delete_effects
    with pytest.raises(PhotoSettingsError, match="unseen"):
        PhotoSettings(unseen="mirror")
    with pytest.raises(PhotoSettingsError, match="delete_shadow"):
        PhotoSettings(delete_shadow=1)
    assert len(PART_DEFAULTS) == len(Part) and set(FLAT_CODES) == {FALLBACK, DEFAULT}
    assert SOURCE_NAMES[PART] == "part" and SOURCE_NAMES[DEFAULT] == "default"


def test_a_turned_car_shows_its_parts_not_one_flat_colour():
    """Seen from behind and turned by 90 degrees, the side the photo barely saw is drawn from the same parts seen
    elsewhere on the car (code ``part``), and the part map names glass, tyres and body on it."""
    scene = _scene([BEHIND])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    edited = apply_edits(scene, [Rotate(12001, math.pi / 2)])
    result = render_photo(image, FRAME, scene, edited, settings=PARTS)
    shares = result.objects[12001]
    assert shares["photo"] + shares["mirror"] + shares["part"] + shares["fallback"] == pytest.approx(1.0, abs=1e-3)
    assert shares["part"] > 0.5 and shares["fallback"] < 0.3
    old = render_photo(image, FRAME, scene, edited, settings=PhotoSettings(relight=False, contact_shadow=0.0,
                                                                          fill="telea", unseen="body"))
    assert old.objects[12001]["fallback"] > 0.9 and old.objects[12001]["part"] == 0.0
    drawn = torch.isin(result.source, torch.tensor([1, 2, FALLBACK, PART, DEFAULT], dtype=torch.uint8))
    labels = set(result.parts[drawn].tolist())
    assert {int(Part.BODY), int(Part.GLASS)} <= labels and -1 not in labels
    assert part_picture(result.parts).shape == (*result.parts.shape, 3)


def test_recolour_of_body_part_keeps_hue_pure():
    """A red body repainted blue with body_part: every repainted pixel has the target's hue (no magenta from an
    additive Lab shift of orange highlights and dark red shades)."""
    shade = torch.linspace(0.25, 1.0, 200)[:, None]
    red = torch.tensor([[0.75, 0.08, 0.05]]) * shade
    orange = torch.tensor([[0.95, 0.45, 0.2]]).repeat(40, 1)  # highlights
    grey = torch.full((30, 3), 0.08)  # a window seen through a loose fit
    colors = torch.cat([red, orange, grey])
    new, body, _ = recolor_pixels(colors, (0.1, 0.25, 0.8), body_part=True)
    assert bool(body[:200].all()) and not bool(body[240:].any())
    painted = new[body]
    assert bool((painted[:, 2] >= painted[:, 0]).all())  # blue dominates red everywhere: no magenta
    assert torch.equal(new[240:], colors[240:])


def test_delete_with_effects_runs_and_marks_what_it_relit():
    scene = _scene([BEHIND])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    edited = apply_edits(scene, [Delete(12001)])
    result = render_photo(image, FRAME, scene, edited, settings=PhotoSettings(delete_effects=True, fill="telea"))
    assert result.image.shape == image.shape and result.objects == {}


def _lit_with_shadow(monkeypatch, scene):
    """The scene's surface colours over grey road, the car's shadow (cast along a fixed light from above and to the
    left, :func:`_cast_shadows`) halved, and that light handed to the photo appearance."""
    from sdn3d.editing.photo import transfer
    from sdn3d.editing.photo.light import LightEstimate
    from sdn3d.scene.maps import posed_meshes

    d = torch.tensor([-0.6, -0.7, 0.2], dtype=torch.float64)
    light = LightEstimate(d / d.norm(), 0.4, 0.5, 1000)
    monkeypatch.setattr(transfer.PhotoSource, "light", lambda self: (None, light))
    image, covered = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    rows, verts, _ = posed_meshes(scene.objects, transfer.default_bank())
    cast = transfer._cast_shadows(scene.objects, [0], {int(rows[0]): verts[0]}, _k_input(), INPUT_SIZE[::-1], light)
    shadow = (cast > 0.5) & ~covered
    assert int(shadow.sum()) > 100
    return torch.where(shadow[None], image * 0.5, image), light


def test_a_moved_car_casts_its_shadow_at_its_new_place(monkeypatch):
    """cast_shadow: the road where the moved car's shadow now falls is darkened by the gain measured on its old
    shadow (about half here) and marked ``shadow``; its old shadow is relit. Without it neither happens."""
    from sdn3d.editing.ops import Move
    from sdn3d.editing.photo import transfer
    from sdn3d.editing.photo.settings import SHADOW
    from sdn3d.scene.maps import posed_meshes

    scene = _scene([BEHIND])
    image, light = _lit_with_shadow(monkeypatch, scene)
    old_shadow = (image[0] < 0.3) & (image[0] - image[2]).abs().lt(1e-6)  # the halved grey road
    edited = apply_edits(scene, [Move(12001, (90.0, 40.0))])
    rows, verts, _ = posed_meshes(edited.objects, transfer.default_bank())
    new_cast = transfer._cast_shadows(edited.objects, [0], {int(rows[0]): verts[0]}, _k_input(), INPUT_SIZE[::-1],
                                      light) > 0.9
    on = PhotoSettings(relight=False, contact_shadow=0.0, fill="telea", delete_effects=False, cast_shadow=True)
    off = PhotoSettings(relight=False, contact_shadow=0.0, fill="telea", delete_effects=False)
    with_cast = render_photo(image, FRAME, scene, edited, settings=on)
    without = render_photo(image, FRAME, scene, edited, settings=off)
    road_now = new_cast & (with_cast.parts < 0) & ~old_shadow & (without.image[0] > 0.4)
    assert int(road_now.sum()) > 50
    assert float(with_cast.image[:, road_now].mean()) < 0.6 * float(without.image[:, road_now].mean())
    assert bool((with_cast.source[road_now] == SHADOW).all())
    left = old_shadow & (with_cast.source == 9) & ~new_cast  # relit, outside the hole and the new shadow
    assert int(left.sum()) > 30
    assert float(with_cast.image[:, left].mean()) > 0.4 and float(without.image[:, left].mean()) < 0.25


def test_removal_fills_on_bounded_crops(monkeypatch):
    """delete_effects' PatchMatch works on crops at most ROAD_FILL_MAX_SIDE on a side (its cost bound), whatever the
    hole's size."""
    from patchmatch import patch_match

    from sdn3d.editing.photo import transfer

    sides = []
    real = patch_match.inpaint

    def spy(image, mask, *args, **kwargs):
        sides.append(max(image.shape[:2]))
        return real(image, mask, *args, **kwargs)

    monkeypatch.setattr(patch_match, "inpaint", spy)
    monkeypatch.setattr(transfer, "ROAD_FILL_MAX_SIDE", 48)
    scene = _scene([SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.3, location=(0.0, 1.6, 7.0))])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    image = image * (0.9 + 0.2 * torch.rand(image.shape[1:], generator=torch.Generator().manual_seed(0)))
    result = render_photo(image.clamp(0, 1), FRAME, scene, apply_edits(scene, [Delete(12001)]),
                          settings=PhotoSettings(fill="patchmatch", delete_effects=True))
    assert result.image.shape == image.shape
    assert sides and max(sides) <= 48
