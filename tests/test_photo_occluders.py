"""Thin things in front of a car (editing.photo.occluders): found where the mask goes round them, kept in front in
every edit."""

from __future__ import annotations

import dataclasses

import torch

from sdn3d.editing.apply import Delete, Move, apply_edits
from sdn3d.editing.photo.occluders import thin_occluders
from sdn3d.editing.photo.settings import IN_FRONT, INPUT, SOURCE_NAMES
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.scene.code import SceneObject
from tests.test_photo import BACKGROUND, CAR, FRAME, INPUT_SIZE, NO_LIGHT, _k_input, _scene, _surface_colors

POLE = (0.1, 0.1, 0.12)


def _car_block() -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """``(image, mask ids, outline ids)``: a grey car 20 rows tall whose outline is its mask."""
    ids = torch.zeros(40, 60, dtype=torch.long)
    ids[10:30, 10:50] = 7
    image = torch.full((3, 40, 60), 0.6)
    image[:, 10:30, 10:50] = torch.tensor([0.7, 0.2, 0.2])[:, None, None]
    return image, ids, ids.clone()


def test_a_pole_across_a_car_is_found_and_an_overshooting_outline_is_not():
    image, mask, outline = _car_block()
    mask[10:30, 28:31] = 0  # a pole three pixels wide crosses the car
    image[:, :, 28:31] = torch.tensor(POLE)[:, None, None]
    outline[10:30, 50:54] = 7  # the template overshoots the car's end by 4 pixels
    found = thin_occluders(image, mask, outline)
    assert bool(found[10:30, 28:31].all())
    assert not bool(found[:, 50:54].any())  # the car's mask on one side only: the car's, not a thing in front
    assert int(found.sum()) == 40 * 3  # the pole runs on above and below the car, in its own colour


def test_a_pole_is_found_where_the_template_overshoots_its_car_all_round():
    """The overshoot ring joins the pole at its ends; the pole is still a strip of its own."""
    image, mask, outline = _car_block()
    outline[6:34, 6:54] = 7
    mask[10:30, 28:31] = 0
    image[:, :, 28:31] = torch.tensor(POLE)[:, None, None]
    found = thin_occluders(image, mask, outline)
    assert bool(found[:, 28:31].all()) and int(found.sum()) == 40 * 3


def test_a_gap_in_the_mask_that_looks_like_the_car_is_the_car():
    image, mask, outline = _car_block()
    mask[10:30, 28:31] = 0  # the mask missed a strip of the car; the pixels are the car's paint
    assert not bool(thin_occluders(image, mask, outline).any())
    short = mask.clone()
    image[:, :, 28:31] = torch.tensor(POLE)[:, None, None]
    short[10:14, 28:31] = 7  # a thing only 16 of the car's 20 rows tall still counts; a stub of 4 does not
    assert bool(thin_occluders(image, short, outline)[14:30, 28:31].all())
    stub = outline.clone()
    stub_mask = outline.clone()
    stub_mask[26:30, 28:31] = 0
    assert not bool(thin_occluders(image, stub_mask, stub).any())


def _pole_scene():
    """A car with a dark pole in front of it: the pole is in the picture and cut out of the car's mask."""
    scene = _scene([CAR])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    cols = scene.objects.mask[0].any(0).nonzero().flatten()
    middle = int(cols.float().mean())
    mask = scene.objects.mask.clone()
    mask[0, :, middle - 1:middle + 1] = False  # 2 working pixels = 4 input pixels
    scene = scene.replace(objects=scene.objects.replace(mask=mask))
    image[:, :, 2 * (middle - 1):2 * (middle + 1)] = torch.tensor(POLE)[:, None, None]
    return scene, image, middle


def test_a_pole_in_front_of_a_car_stays_when_the_car_is_deleted_or_moved_away():
    scene, image, middle = _pole_scene()
    pole = torch.zeros(INPUT_SIZE[::-1], dtype=torch.bool)
    pole[:, 2 * (middle - 1):2 * (middle + 1)] = True
    for ops in ([Delete(12001)], [Move(12001, (20.0, 40.0))]):
        result = render_photo(image, FRAME, scene, apply_edits(scene, ops), settings=NO_LIGHT)
        kept = result.source == IN_FRONT
        assert int(kept.sum()) > 50 and not bool((kept & ~pole).any())
        assert torch.equal(result.image[:, pole], image[:, pole])  # the whole pole is still there, nothing else kept
        assert SOURCE_NAMES[IN_FRONT] == "in front"
        off = render_photo(image, FRAME, scene, apply_edits(scene, ops),
                           settings=dataclasses.replace(NO_LIGHT, keep_in_front=False))
        assert not torch.equal(off.image[:, pole], image[:, pole])  # without it, the delete's fill paints it over
        # ... and smears the pole into the road beside it; kept, the pole is no source of the fill.
        beside = torch.zeros_like(pole)
        beside[:, 2 * (middle - 1) - 6:2 * (middle - 1) - 1] = True
        beside[:, 2 * (middle + 1) + 1:2 * (middle + 1) + 6] = True
        beside &= result.source != INPUT
        assert float((result.image[:, beside] - BACKGROUND).abs().mean()) < 0.02
        assert float((off.image[:, beside] - BACKGROUND).abs().mean()) > 0.04


def test_a_car_moved_nearer_than_the_pole_hides_it():
    """The pole stood in front of the car at 12 m; brought to 6 m along its line of sight the car is in front."""
    scene, image, middle = _pole_scene()
    nearer = scene.objects.location[0] * 0.5
    moved = scene.replace(objects=scene.objects.replace(location=nearer[None]))
    result = render_photo(image, FRAME, scene, moved, settings=NO_LIGHT)
    _, car_now = _surface_colors(moved, INPUT_SIZE[::-1], _k_input())
    kept = result.source == IN_FRONT
    assert int(kept.sum()) > 0  # where the car stood, the pole is still there ...
    assert not bool((kept & car_now).any())  # ... but not over the car now nearer than it
    far = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.4, location=(-1.0, 1.6, 14.0))
    behind = scene.replace(objects=scene.objects.replace(location=torch.tensor([far.location],
                                                                              dtype=scene.objects.location.dtype)))
    result = render_photo(image, FRAME, scene, behind, settings=NO_LIGHT)
    assert int((result.source == IN_FRONT).sum()) > 0  # pushed 2 m farther back, it stays behind the pole


def test_components_are_scipy_labels_4_connected():
    """The strips' components (OpenCV, issue 40: no scipy import on the edit path) are scipy.ndimage.label's default
    4-connected ones, up to their numbering, on random masks where pixels touch diagonally."""
    from scipy import ndimage

    from sdn3d.editing.photo.occluders import _components

    gen = torch.Generator().manual_seed(0)
    for density in (0.3, 0.5, 0.7):
        mask = torch.rand(40, 57, generator=gen) < density
        labels, count = _components(mask[3:])  # a slice, as _strips gets the outlines' rows
        expected, expected_count = ndimage.label(mask[3:].numpy())
        assert count == expected_count and labels.dtype == torch.int64
        assert (labels > 0).equal(mask[3:])
        pairs = torch.stack([labels[mask[3:]], torch.from_numpy(expected).long()[mask[3:]]], 1).unique(dim=0)
        assert len(pairs) == count  # one scipy component per OpenCV one, and back
