"""Composing an edit at the input's resolution (issue 19, point 1): untouched pixels are the input's, bit for bit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import torch
from helpers.tiny_models import geometric_net, textural_spec

from sdn3d.data import vkitti1
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth
from sdn3d.editing.appearance import render_maps
from sdn3d.editing.apply import Delete, Rotate, SetCode, apply_edits
from sdn3d.editing.compose import (
    ComposeSettings,
    ComposeSettingsError,
    compose_edited,
    edit_region_mask,
    edited_object_ids,
    feather_alpha,
)
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.inputs import fit_image
from sdn3d.editing.render import edit_image
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.image_ops import to_image_tensor
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.models import Models
from sdn3d.scene.maps import scene_maps
from sdn3d.textural.renderer import TexturalRenderer

SIZE = (160, 64)


@pytest.fixture(scope="module")
def models() -> Models:
    torch.manual_seed(0)
    return Models(None, GeometricPredictor(geometric_net()), TexturalRenderer(textural_spec()), crop_size=32)


@pytest.fixture(scope="module")
def record(tiny_synth):
    return vkitti1.read_frames(tiny_synth)[4]


def _random_uint8(height: int, width: int, seed: int = 0) -> torch.Tensor:
    return torch.randint(0, 256, (3, height, width), generator=torch.Generator().manual_seed(seed), dtype=torch.uint8)


def _expected_touched(region: torch.Tensor, transform: PixelFrame) -> torch.Tensor:
    """``(H_in, W_in)`` bool: input pixels inside the crop whose bilinear sample touches a region pixel (written
    out per pixel with the PixelFrame rule, independent of the module's window and grid code)."""
    (win, hin), (w, h) = transform.input_size, transform.working_size
    touched = torch.zeros(hin, win, dtype=torch.bool)
    padded = torch.nn.functional.pad(region.float(), (1, 1, 1, 1))  # index + 1
    for i in range(hin):
        for j in range(win):
            u, v = transform.to_working((j, i))
            if not (-0.5 <= u <= w - 0.5 and -0.5 <= v <= h - 0.5):
                continue
            cu, cv = min(max(u, 0.0), w - 1.0), min(max(v, 0.0), h - 1.0)  # border padding
            ju, iv = int(np.floor(cu)), int(np.floor(cv))
            near = padded[iv + 1:iv + 3, ju + 1:ju + 3]
            touched[i, j] = bool(near.any())
    return touched


@pytest.mark.parametrize("input_size", [(80, 32), (200, 120), (96, 64), (150, 30)])
def test_untouched_pixels_are_the_inputs_bit_for_bit(input_size):
    """Working size 40x16. Plain resize (80x32), a vertical crop (200x120: scaled 40x24, rows 4-19 kept;
    96x64: scaled 40x27, an upscale), a horizontal crop (150x30: scaled 80x16, columns 20-59 kept)."""
    work = (40, 16)
    transform = PixelFrame(input_size, work) if input_size == (80, 32) else _cover(input_size, work)
    original = _random_uint8(input_size[1], input_size[0])
    generated = torch.rand(3, work[1], work[0], generator=torch.Generator().manual_seed(1))
    colour = torch.tensor([0.2, 0.6, 1.0])
    generated[:, 4:8, 13:22] = colour[:, None, None]  # one colour deep inside the first box
    region = torch.zeros(work[1], work[0], dtype=torch.bool)
    region[3:9, 10:25] = True
    region[0:4, 0:3] = True  # touches the top-left corner of the working frame (a crop edge when cropped)
    out = compose_edited(original, generated, region, transform, feather_px=2)
    assert out.dtype == torch.uint8 and out.shape == original.shape
    touched = _expected_touched(region, transform)
    untouched = ~touched
    assert torch.equal(out[:, untouched], original[:, untouched])  # bit for bit
    changed = (out != original).any(0)
    assert bool(changed.any()) and not bool((changed & untouched).any())
    # Deep inside the region (alpha 1) the picture is the generator's, upsampled: here one colour.
    u, v = transform.to_input((17, 6))
    i, j = int(round(v)), int(round(u))
    assert out[:, i, j].tolist() == (colour * 255).round().tolist()


def _cover(input_size, work):
    from sdn3d.editing.inputs import fit_transform

    transform = fit_transform(work, input_size)
    assert not transform.is_plain_resize
    return transform


def test_pixels_outside_the_crop_are_never_taken_from_the_generator():
    work = (40, 16)
    transform = _cover((60, 60), work)  # square input: the crop keeps a horizontal band
    original = _random_uint8(60, 60)
    generated = torch.ones(3, work[1], work[0])
    region = torch.ones(work[1], work[0], dtype=torch.bool)  # the whole working frame is edited
    out = compose_edited(original, generated, region, transform, feather_px=3)
    top, bottom = transform.to_input((0, -0.5))[1], transform.to_input((0, work[1] - 0.5))[1]
    rows = torch.arange(60, dtype=torch.float64)
    outside = (rows < top) | (rows > bottom)
    assert bool(outside.any()) and torch.equal(out[:, outside], original[:, outside])
    middle = 30
    assert bool((out[:, middle, 25:35] == 255).all())  # inside the crop, far from its edges: the generator's


def test_float_original_keeps_its_values_exactly_and_compose_full_is_the_generators_picture(models, record):
    frame = load_frame(record, SIZE, semantic=True, instances=True)
    gt = ground_truth(record, SIZE)
    full = edit_image(frame.image, frame.intrinsics, [], models, "gt", gt, compose="full", min_pixels=1,
                      appearance="generator")
    torch.testing.assert_close(full.edited, full.generated)
    assert full.region is None and full.edited.shape == (3, SIZE[1], SIZE[0])
    nothing = edit_image(frame.image, frame.intrinsics, [], models, "gt", gt, min_pixels=1, appearance="generator")
    assert torch.equal(nothing.edited, frame.image) and not bool(nothing.region.any())  # nothing edited: the input
    victim = int(full.scene.objects.instance_id[0])
    deleted = edit_image(frame.image, frame.intrinsics, [Delete(victim)], models, "gt", gt, min_pixels=1,
                         appearance="generator")
    torch.testing.assert_close(deleted.generated, render_maps(deleted.maps, models.textural))
    region = deleted.region
    was = frame.instances == victim  # the deleted car's pixels are in the region, and they changed
    assert bool(region[was].all())
    assert not torch.equal(deleted.edited[:, was], frame.image[:, was])
    far = ~torch.nn.functional.max_pool2d(region[None, None].float(), 3, 1, 1)[0, 0].bool()
    assert bool(far.any()) and torch.equal(deleted.edited[:, far], frame.image[:, far])


def test_edit_image_at_the_inputs_resolution_through_a_crop(models, record):
    """A 240x120 input (not Virtual KITTI's aspect): fit_image scales and crops; the result has the input's
    size and every pixel off the edit region is the input's uint8 value."""
    from PIL import Image

    rgb = np.array(Image.fromarray(vkitti1.load_rgb(record)).resize((240, 120)))
    intr = VKITTI_INTRINSICS.resized(240, 120)
    image, intr_work, transform = fit_image(rgb, intr, SIZE)
    assert not transform.is_plain_resize
    original = torch.from_numpy(np.ascontiguousarray(rgb)).permute(2, 0, 1)
    full = ground_truth(record, transform.scaled_size)  # the oracle's maps, scaled and cropped like the image
    left, top = transform.offset
    crop = (slice(top, top + SIZE[1]), slice(left, left + SIZE[0]))
    gt = dataclasses.replace(full, semantic=full.semantic[crop], instances=full.instances[crop], boxes={})
    ids, counts = gt.instances[gt.instances >= 1000].unique(return_counts=True)
    ids = ids[counts.argsort(descending=True)].tolist()
    ops = [Rotate(ids[0], 0.8), Delete(ids[1])]
    result = edit_image(image, intr_work, ops, models, "gt", gt, original=original, transform=transform,
                        min_pixels=1, appearance="generator")
    assert result.edited.shape == original.shape and result.edited.dtype == torch.uint8
    touched = _expected_touched(result.region, transform)
    assert torch.equal(result.edited[:, ~touched], original[:, ~touched])
    assert bool((result.edited != original).any())
    with pytest.raises(ValueError, match="aspect ratio"):
        edit_image(image, intr_work, ops, models, "gt", gt, original=original, min_pixels=1, appearance="generator")


def test_region_covers_source_and_target_footprints_and_vacated_pixels(record):
    from sdn3d.data.scene_gt import scene_from_frame

    scene = scene_from_frame(record, SIZE)
    ids = scene.objects.instance_id.tolist()
    moved = apply_edits(scene, [Rotate(ids[0], 0.7), Delete(ids[1])])
    recoloured = apply_edits(scene, [SetCode(ids[2], tuple([1.0] * scene.code_dim))])
    assert edited_object_ids(scene.objects, moved.objects).tolist() == sorted(ids[:2])
    assert edited_object_ids(scene.objects, recoloured.objects).tolist() == [ids[2]]
    assert edited_object_ids(scene.objects, scene.objects).numel() == 0
    grown = scene.objects.replace(mask=scene.objects.mask | scene.objects.mask.roll(3, dims=2))  # masks only
    assert edited_object_ids(scene.objects, grown).numel() == 0
    empty = scene.objects.select(torch.zeros(len(ids), dtype=torch.bool))
    assert edited_object_ids(empty, empty).numel() == 0 and edited_object_ids(empty, scene.objects).tolist() == ids
    before, after = scene_maps(scene), scene_maps(moved)
    region = edit_region_mask(before, after, edited_object_ids(scene.objects, moved.objects), dilate_px=0)
    for iid in ids[:2]:
        assert bool(region[before.instance == iid].all())  # source footprints (incl. the deleted car's)
    assert bool(region[after.instance == ids[0]].all())  # target footprint
    others = torch.isin(before.instance, torch.tensor(ids[2:])) & (before.instance == after.instance)
    assert not bool((region & others & ~torch.isin(after.instance, torch.tensor(ids[:2]))).all())
    unchanged = edit_region_mask(before, before, torch.zeros(0, dtype=torch.long), dilate_px=3)
    assert not bool(unchanged.any())
    grown = edit_region_mask(before, after, edited_object_ids(scene.objects, moved.objects), dilate_px=2)
    assert bool((grown & ~region).any()) and not bool((region & ~grown).any())


def test_feather_alpha_is_zero_outside_and_one_deep_inside():
    region = torch.zeros(20, 30, dtype=torch.bool)
    region[2:18, 5:25] = True
    alpha = feather_alpha(region, 4)
    assert bool((alpha[~region] == 0).all()) and bool((alpha[region] > 0).all())
    assert bool((alpha[6:14, 9:21] == 1).all())  # 4 pixels deep and more
    assert 0 < float(alpha[2, 12]) < float(alpha[3, 12]) < float(alpha[4, 12]) < 1  # a ramp from the edge
    at_frame_edge = torch.zeros(20, 30, dtype=torch.bool)
    at_frame_edge[:, :10] = True
    assert float(feather_alpha(at_frame_edge, 4)[10, 0]) == 1  # the frame's edge is no seam
    assert float(feather_alpha(at_frame_edge, 4, (True, False, False, False))[10, 0]) < 1  # a crop edge is
    assert torch.equal(feather_alpha(region, 0), region.float())


def test_compose_settings_are_checked():
    assert ComposeSettings().to_dict() == {"mode": "edited", "dilate_px": 4, "feather_px": 4}
    with pytest.raises(ComposeSettingsError, match="compose must be one of"):
        ComposeSettings(mode="partial")
    with pytest.raises(ComposeSettingsError, match="compose_dilate_px must be an integer"):
        ComposeSettings(dilate_px=-1)
    with pytest.raises(ComposeSettingsError, match="compose_feather_px must be an integer"):
        ComposeSettings(feather_px=2.5)


def test_shapes_are_checked():
    transform = PixelFrame((80, 32), (40, 16))
    with pytest.raises(ValueError, match="working size"):
        compose_edited(_random_uint8(32, 80), torch.rand(3, 16, 41), torch.zeros(16, 40, dtype=torch.bool), transform)
    with pytest.raises(ValueError, match="input size"):
        compose_edited(_random_uint8(30, 80), torch.rand(3, 16, 40), torch.zeros(16, 40, dtype=torch.bool), transform)
    float_in = to_image_tensor(np.zeros((32, 80, 3), np.uint8))
    region = torch.zeros(16, 40, dtype=torch.bool)
    region[5, 5] = True
    out = compose_edited(float_in, torch.ones(3, 16, 40), region, transform, 1)
    assert out.dtype == torch.float32 and float(out.max()) > 0
