"""What a removal's hole takes beyond the removed car's mask and fitted silhouette (issue 41, session 21): the pieces
of the car both missed, a side mirror jutting out of its outline (:func:`~sdn3d.editing.photo.fill.leftover_pieces`),
and nothing that runs on beyond them (a pole, a lane line) or belongs to an object that stays."""

from __future__ import annotations

import pytest
import torch

from sdn3d.editing.apply import Delete, apply_edits
from sdn3d.editing.photo.fill import leftover_pieces
from sdn3d.editing.photo.road import PictureLab
from sdn3d.editing.photo.settings import FILL, INPUT, PhotoSettings, PhotoSettingsError
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.image_ops import dilate_square
from sdn3d.scene.code import SceneObject

pytestmark = pytest.mark.usefixtures("one_torch_thread")

RED, GREY, WHITE, POLE, BLUE = (0.75, 0.1, 0.1), (0.45, 0.45, 0.45), (0.95, 0.95, 0.95), (0.2, 0.2, 0.22), \
    (0.1, 0.2, 0.8)


def _paint(image: torch.Tensor, rows: slice, cols: slice, colour: tuple[float, float, float]) -> None:
    image[:, rows, cols] = torch.tensor(colour)[:, None, None]


def _street() -> tuple[torch.Tensor, torch.Tensor, dict[str, torch.Tensor]]:
    """``(image (3, 96, 160), ids (96, 160), parts)``: grey road with a little grain; a red car (id 7, rows 30-79,
    columns 50-109, its mask) with a red mirror jutting 6 pixels out of its left side (rows 44-48, columns 44-49: not
    in the mask); a dark pole from the top to row 89 touching the car's right side (columns 110-111); a white lane
    line across the picture in rows 83-84; a blue car that stays (id 9, rows 30-79, columns 114-139); a red fleck
    near the car but apart from its hole (rows 24-25, columns 40-41)."""
    gen = torch.Generator().manual_seed(0)
    image = torch.tensor(GREY)[:, None, None] + 0.015 * torch.randn(3, 96, 160, generator=gen)
    _paint(image, slice(30, 80), slice(50, 110), RED)
    _paint(image, slice(44, 49), slice(44, 50), RED)
    _paint(image, slice(0, 90), slice(110, 112), POLE)
    _paint(image, slice(83, 85), slice(0, 160), WHITE)
    _paint(image, slice(30, 80), slice(114, 140), BLUE)
    _paint(image, slice(24, 26), slice(40, 42), RED)
    ids = torch.zeros(96, 160, dtype=torch.long)
    ids[30:80, 50:110] = 7
    ids[30:80, 114:140] = 9
    parts = {"mirror": torch.zeros(96, 160, dtype=torch.bool), "fleck": torch.zeros(96, 160, dtype=torch.bool)}
    parts["mirror"][44:49, 44:50] = True
    parts["fleck"][24:26, 40:42] = True
    return image.clamp(0, 1).float(), ids, parts


def test_the_hole_takes_a_mirror_its_mask_missed_and_nothing_that_runs_on_beyond_it():
    image, ids, parts = _street()
    hole = dilate_square(ids == 7, 3) & (ids != 9)
    keep = ids == 9
    assert not bool((hole & parts["mirror"]).all())  # the mask's hole leaves the mirror's tip (columns 44-46)
    found = leftover_pieces(PictureLab(image), hole, ids, torch.tensor([7]), keep, 0.1, 12.0)  # r = 5 pixels
    assert bool(found[parts["mirror"] & ~hole].all())  # the whole tip
    assert not bool((found & keep).any())  # an object that stays keeps its pixels
    assert not bool(found[:, 110:112].any())  # the pole runs on above and below: scene, not car
    assert not bool(found[83:85].any())  # so does the lane line
    assert not bool((found & parts["fleck"]).any())  # car-coloured but not attached to the hole
    # Nothing but the mirror and its one-pixel rim.
    assert not bool((found & ~dilate_square(parts["mirror"], 1)).any())
    # Beyond the reach: none of it.
    far = leftover_pieces(PictureLab(image), hole, ids, torch.tensor([7]), keep, 0.0, 12.0)
    assert not bool(far.any())


def test_a_kerb_behind_the_roof_cut_off_between_two_poles_is_no_leftover():
    """Above the roof a pale kerb runs behind the car, cut into a short piece by two poles: cut off from farther out
    like a mirror, but wholly above the roof, it is what stands behind the car."""
    image, ids, parts = _street()
    _paint(image, slice(0, 30), slice(0, 160), (0.15, 0.3, 0.12))  # trees
    _paint(image, slice(23, 27), slice(0, 160), (0.95, 0.93, 0.7))  # the kerb, just above the roof's hole
    _paint(image, slice(0, 30), slice(60, 62), POLE)
    _paint(image, slice(0, 30), slice(90, 92), POLE)
    hole = dilate_square(ids == 7, 3) & (ids != 9)
    found = leftover_pieces(PictureLab(image), hole, ids, torch.tensor([7]), ids == 9, 0.1, 12.0)
    assert not bool(found[:27].any())
    assert bool(found[parts["mirror"] & ~hole].all())  # the mirror still goes


def test_a_piece_that_looks_like_the_road_around_it_is_no_leftover():
    image, ids, parts = _street()
    _paint(image, slice(44, 49), slice(44, 50), GREY)  # no mirror: the same grey as the road
    hole = dilate_square(ids == 7, 3) & (ids != 9)
    found = leftover_pieces(PictureLab(image), hole, ids, torch.tensor([7]), ids == 9, 0.1, 12.0)
    assert not bool(found.any())


def test_leftover_settings_are_checked_by_name():
    for name, bad in (("leftover_reach", -0.1), ("leftover_reach", 0.6), ("leftover_step", "x")):
        with pytest.raises(PhotoSettingsError, match=name):
            PhotoSettings(**{name: bad})
    assert PhotoSettings().leftover_reach > 0  # on by default


def test_a_car_too_small_for_the_reach_is_not_searched():
    """Under LEFTOVER_MIN_PX of reach (a car 30 pixels tall at 0.06) nothing is taken: what so short a reach cuts off
    is the lines along the hole's edge, and the hole's rim covers a mirror of a pixel."""
    image, ids, parts = _street()
    hole = dilate_square(ids == 7, 3) & (ids != 9)
    found = leftover_pieces(PictureLab(image), hole, ids, torch.tensor([7]), ids == 9, 0.05, 12.0)  # r = 2.5 -> 2
    assert not bool(found.any())


def test_a_delete_fills_a_mirror_outside_the_cars_mask_and_silhouette():
    """A car of the synthetic scenes (its mask is its template's silhouette) with a mirror painted in its own colour
    just outside its hole: the delete takes the mirror with the car (main's hole, mask and silhouette grown by 3
    pixels, left it as a fleck)."""
    from tests.test_photo import FRAME, _k_input, _scene, _surface_colors

    near = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.4, location=(-0.5, 1.6, 6.0))
    scene = _scene([near])  # about 50 input pixels tall: a reach of 3 pixels (photo.leftover_reach 0.06)
    image, covered = _surface_colors(scene, FRAME.input_size[::-1], _k_input())
    gen = torch.Generator().manual_seed(1)
    image = torch.where(covered[None], image, image + 0.01 * torch.randn(image.shape, generator=gen))
    # The mirror: 4 rows at the car's middle height, from 2 to 5 pixels left of its leftmost pixel in those rows.
    rows = covered.any(1).nonzero().flatten()
    mid = int(rows[len(rows) // 2])
    left = int(covered[mid - 2:mid + 2].any(0).nonzero().min())
    mirror = torch.zeros_like(covered)
    mirror[mid - 2:mid + 2, left - 5:left] = True
    colour = image[:, mid - 2:mid + 2, left:left + 3].mean((1, 2))
    image = torch.where(mirror[None], colour[:, None, None], image).clamp(0, 1)
    edited = apply_edits(scene, [Delete(12001)])
    off = render_photo(image, FRAME, scene, edited, settings=PhotoSettings(leftover_reach=0.0))
    assert bool((off.source[mirror] == INPUT).any())  # the mask's and silhouette's hole leaves the mirror's tip
    now = render_photo(image, FRAME, scene, edited, settings=PhotoSettings())
    assert bool((now.source[mirror] == FILL).all())
    road = torch.tensor([0.45, 0.45, 0.45])
    err = (now.image[:, mirror] - road[:, None]).abs()
    assert float(err.mean()) < 0.03  # road where the mirror was (0.018; with leftover_reach 0, the mirror: 0.06)
    assert float((off.image[:, mirror] - road[:, None]).abs().mean()) > 0.05
