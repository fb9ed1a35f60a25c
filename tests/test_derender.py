"""De-rendering an image into a SceneCode and rendering it back (tiny random-weight branches)."""

from __future__ import annotations

import pytest
import torch
from helpers.tiny_models import geometric_net, semantic_net, textural_spec, write_checkpoints

from sdn3d.data import vkitti1
from sdn3d.data.datasets import GeometricDataset, ObjectFilter
from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth, scene_from_frame
from sdn3d.derender import derender, encode_scene
from sdn3d.editing.appearance import render_maps
from sdn3d.editing.apply import Delete
from sdn3d.editing.pick import projected_centers
from sdn3d.editing.render import edit_image, render
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.image_ops import (
    InputPhoto,
    crop_intrinsics,
    crop_windows,
    instance_label_map,
    mask_boxes,
    pixel_centre_boxes,
    resize_image,
    square_crop_window,
)
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.models import Models, geometric_crop_settings
from sdn3d.scene.maps import scene_maps
from sdn3d.semantic.predict import Segmentation, SemanticPredictor
from sdn3d.textural.renderer import TexturalRenderer

SIZE = (160, 64)


def gt(record):
    return ground_truth(record, SIZE)
CAR, VAN, ROAD = 12, 13, 5


@pytest.fixture(scope="module")
def frame(tiny_synth):
    record = vkitti1.read_frames(tiny_synth)[4]  # the benchmark's source frame
    return record, load_frame(record, SIZE, semantic=True, instances=True)


@pytest.fixture(scope="module")
def models() -> Models:
    torch.manual_seed(0)
    return Models(SemanticPredictor(semantic_net(), "vkitti"), GeometricPredictor(geometric_net()),
                  TexturalRenderer(textural_spec()), crop_size=32, margin=0.1)


class Spy(GeometricPredictor):
    """Records what the geometric branch is given."""

    def __init__(self, net) -> None:
        super().__init__(net)
        self.calls: list[dict] = []

    def predict(self, crop, mask, box, intrinsics, crop_intrinsics=None, ignore=None, refine=None, lamp_mask=None,
                image_width=None):
        self.calls.append({"crop": crop, "mask": mask, "box": box, "intrinsics": intrinsics, "ignore": ignore,
                           "refine": refine, "lamp_mask": lamp_mask, "image_width": image_width})
        return super().predict(crop, mask, box, intrinsics, crop_intrinsics, ignore, refine, lamp_mask,
                               image_width=image_width)


def _one_window(maps, left, top, side, out_size, mode):
    """The sampling rule written out for one window: output pixel j samples u = left + (j + 0.5) side / S - 0.5."""
    _, height, width = maps.shape
    centres = (torch.arange(out_size, dtype=torch.float32) + 0.5) * (side / out_size) - 0.5
    u = (left + centres) * (2.0 / width) + (1.0 / width - 1.0)
    v = (top + centres) * (2.0 / height) + (1.0 / height - 1.0)
    grid = torch.stack(torch.meshgrid(u, v, indexing="xy"), dim=-1)
    return torch.nn.functional.grid_sample(maps[None].float(), grid[None], mode=mode, padding_mode="zeros",
                                           align_corners=False)[0]


def test_crop_windows_follow_the_sampling_rule_window_by_window():
    maps = torch.rand(2, 20, 30)
    windows = torch.tensor([[3.0, 4.0, 9.0], [-5.0, 12.0, 14.0], [25.0, -3.0, 7.0]])  # partly outside too
    for mode in ("bilinear", "nearest"):
        got = crop_windows(maps, windows, 16, mode)
        assert got.shape == (3, 2, 16, 16)
        for i, (left, top, side) in enumerate(windows.long().tolist()):
            assert torch.equal(got[i], _one_window(maps, left, top, side, 16, mode))
    per_window = torch.rand(3, 1, 20, 30)
    one = crop_windows(per_window, windows, 8, "nearest")
    torch.testing.assert_close(one[1], _one_window(per_window[1], -5, 12, 14, 8, "nearest"))


def test_antialiased_crops_are_box_filtered_and_small_windows_unchanged():
    maps = torch.rand(3, 40, 60)
    # A window of 32 pixels read into 8: each crop pixel is the mean of its 4 x 4 block (samples at pixel centres).
    got = crop_windows(maps, torch.tensor([[5.0, 3.0, 32.0]]), 8, "bilinear", antialias=True)
    torch.testing.assert_close(got[0], torch.nn.functional.avg_pool2d(maps[:, 3:35, 5:37][None], 4)[0])
    # Windows at most the crop's size are sampled as without the filter, also beside a large one.
    windows = torch.tensor([[3.0, 4.0, 7.0], [2.0, 1.0, 30.0], [-2.0, 5.0, 8.0]])
    both = crop_windows(maps, windows, 8, "bilinear", antialias=True)
    plain = crop_windows(maps, windows, 8, "bilinear")
    assert torch.equal(both[[0, 2]], plain[[0, 2]]) and not torch.allclose(both[1], plain[1])
    # (left, top, width, height) windows: the same rule per axis.
    wide = crop_windows(maps, torch.tensor([[3.0, 4.0, 7.0, 7.0]]), 8, "bilinear")
    assert torch.equal(wide, plain[:1])


def test_input_photo_crops_cover_the_working_windows_region():
    photo = torch.rand(3, 48, 128)  # a working image of 64 x 24 is this photo halved
    inp = InputPhoto(photo, (0.5, 0.5))
    windows = torch.tensor([[10.0, 2.0, 16.0], [40.0, 5.0, 4.0]])
    assert inp.windows(windows).tolist() == [[20.0, 4.0, 32.0, 32.0], [80.0, 10.0, 8.0, 8.0]]
    crops = inp.crops(windows, 8)
    # The 32-pixel window of the photo read into 8: the mean of each 4 x 4 block of the photo's own pixels.
    torch.testing.assert_close(crops[0], torch.nn.functional.avg_pool2d(photo[:, 4:36, 20:52][None], 4)[0])
    torch.testing.assert_close(crops[1], photo[:, 10:18, 80:88])
    # A scaled and cropped working image: the window's edges map as u_in = (u_work + left) / sx.
    shifted = InputPhoto(photo, (0.25, 0.5), (3, 1))
    assert shifted.windows(windows[:1]).tolist() == [[52.0, 6.0, 64.0, 32.0]]
    with pytest.raises(ValueError, match="scale"):
        InputPhoto(photo, (0.0, 1.0))


def test_derender_reads_the_geometric_crops_from_the_photo(frame, models):
    """The branch's crops come from the photo at its own resolution (the windows the working image's would be), the
    masks from the working size, and the lamp cue reads only the crop pixels surely inside the mask."""
    record, f = frame
    photo = torch.rand(3, SIZE[1] * 2, SIZE[0] * 2)
    image = resize_image(photo, SIZE)  # the working image is the photo halved (area)
    spy = Spy(models.geometric.net)
    spied = Models(None, spy, models.textural, crop_size=32, margin=0.1)
    plain = derender(image, f.intrinsics, spied, "gt", gt(record), min_pixels=1)
    scene = derender(image, f.intrinsics, spied, "gt", gt(record), min_pixels=1, photo=InputPhoto(photo, (0.5, 0.5)))
    before, call = spy.calls
    assert scene.meta["crops_from"] == "photo" and plain.meta["crops_from"] == "image"
    assert before["lamp_mask"] is None
    torch.testing.assert_close(call["mask"], before["mask"])  # the masks: the working size's, same windows
    boxes = call["box"]
    windows = torch.tensor([square_crop_window(b, 0.1) for b in boxes], dtype=torch.float32)
    read = crop_windows(photo, windows * 2, 32, "bilinear", antialias=True)
    torch.testing.assert_close(call["crop"], read * call["mask"])
    assert not torch.allclose(call["crop"], before["crop"])
    # The lamps' pixels: inside the mask, and at least half a working pixel in from its edge (every working pixel
    # within half a pixel of a lamp pixel is the object's).
    sure, whole = call["lamp_mask"] > 0.5, call["mask"] > 0.5
    assert bool((sure <= whole).all()) and 0 < int(sure.sum()) < int(whole.sum())
    masks = scene.objects.mask[scene.objects.has_geometry]
    for i, (left, top, side) in enumerate(windows.tolist()):
        centres = (torch.arange(32) + 0.5) * (side / 32) - 0.5
        v, u = torch.meshgrid(top + centres, left + centres, indexing="ij")
        rows, cols = sure[i, 0].nonzero().unbind(1)
        for dv in (-0.499, 0.499):
            for du in (-0.499, 0.499):
                y, x = (v[rows, cols] + dv).round().long(), (u[rows, cols] + du).round().long()
                assert bool(masks[i][y, x].all())


def test_crop_intrinsics_follow_crop_and_resize():
    windows = torch.tensor([[3.0, 4.0, 9.0], [-5.0, 12.0, 14.0]])
    got = crop_intrinsics(VKITTI_INTRINSICS, windows, 32)
    for i, (left, top, side) in enumerate(windows.long().tolist()):
        ref = VKITTI_INTRINSICS.cropped(left, top, side, side).resized(32, 32)
        torch.testing.assert_close(got[i], torch.tensor([ref.fx, ref.fy, ref.cx, ref.cy]))


def test_mask_boxes_are_half_open_and_convert_to_pixel_centres():
    masks = torch.zeros(3, 10, 12, dtype=torch.bool)
    masks[0, 2:5, 3:9] = True
    masks[1, 9, 0] = True
    boxes = mask_boxes(masks)
    assert boxes.dtype == torch.long
    assert boxes.tolist() == [[3, 2, 9, 5], [0, 9, 1, 10], [0, 0, 0, 0]]
    assert pixel_centre_boxes(boxes[:2]).tolist() == [[3.0, 2.0, 8.0, 4.0], [0.0, 9.0, 0.0, 9.0]]


def test_gt_proposals_feed_the_dataset_crops_to_one_geometric_forward(frame, models):
    record, f = frame
    spy = Spy(models.geometric.net)
    spied = Models(None, spy, models.textural, crop_size=32, margin=0.1)
    scene = derender(f.image, f.intrinsics, spied, "gt", gt(record), min_pixels=1)
    assert len(spy.calls) == 1  # every object in one batched forward
    obj = scene.objects
    ids = f.instances.unique()
    assert obj.instance_id.tolist() == ids[ids > 0].tolist()
    assert torch.equal(obj.mask, f.instances[None] == obj.instance_id[:, None, None])
    assert bool(obj.has_geometry.all()) and bool(obj.observed.all())
    # The semantic map is the frame's, with object pixels labelled by their object's class.
    assert torch.equal(scene.semantic, instance_label_map(f.semantic, f.instances)[0])
    call = spy.calls[0]
    dataset = GeometricDataset([record], SIZE, crop_size=32, margin=0.1, object_filter=ObjectFilter(0, 1.01, 1.01))
    compared = 0
    for item in dataset:
        tid = int(item["track_id"])
        row = [i for i, iid in enumerate(obj.instance_id.tolist()) if iid % INSTANCE_DIVISOR == tid + 1]
        if not row:
            continue
        r = row[0]
        compared += 1
        torch.testing.assert_close(call["box"][r], item["box"])
        torch.testing.assert_close(call["intrinsics"][r], item["intrinsics"])
        torch.testing.assert_close(call["mask"][r], item["mask"])
        torch.testing.assert_close(call["crop"][r], item["crop"], atol=1e-5, rtol=0)
    assert compared >= 2
    # The stored geometry is the predictor's output for those inputs.
    pred = models.geometric.predict(call["crop"], call["mask"], call["box"], call["intrinsics"])
    torch.testing.assert_close(obj.location, pred["location"].double())
    torch.testing.assert_close(obj.dims, pred["dims"].double())
    torch.testing.assert_close(obj.ry, pred["ry"].double())
    assert torch.equal(obj.template_id, pred["template_id"]) and torch.equal(obj.phi, pred["phi"])


def test_codes_are_the_encoders_region_means(frame, models):
    record, f = frame
    scene = derender(f.image, f.intrinsics, models, "gt", gt(record), min_pixels=10**6)
    assert not bool(scene.objects.has_geometry.any()) and bool(scene.objects.has_mask.all())  # too small: 2D only
    _, L = instance_label_map(f.semantic, f.instances)
    feats = models.textural.encoder.model(f.image[None] * 2 - 1)[0]  # (C, H, W) per-pixel features
    for k, iid in enumerate(scene.objects.instance_id.tolist()):
        torch.testing.assert_close(scene.objects.code[k], feats[:, L == iid].mean(1), atol=1e-5, rtol=1e-4)
    present = set(L.unique().tolist())
    for cls in range(14):
        expected = feats[:, L == cls].mean(1) if cls in present else torch.zeros(5)
        torch.testing.assert_close(scene.background_codes[cls], expected, atol=1e-5, rtol=1e-4)
    # encode_scene on the ground-truth scene (composed L) gives the same object codes.
    oracle = encode_scene(scene_from_frame(record, SIZE), f.image, models.textural)
    for k, iid in enumerate(scene.objects.instance_id.tolist()):
        torch.testing.assert_close(oracle.objects.code[oracle.objects.index_of(iid)], scene.objects.code[k])


def test_semantic_proposals_and_small_objects_keep_their_masks(models):
    label = torch.full((1, 32, 48), ROAD)
    instance = torch.zeros(1, 32, 48, dtype=torch.long)
    instance[0, 10:20, 5:25] = CAR * 1000 + 1     # 200 px: gets geometry
    instance[0, 25:28, 30:33] = VAN * 1000 + 7    # 9 px: mask only
    instance[0, 0:4, 40:48] = ROAD * 1000 + 1     # not an instance class: dropped
    instance[0, 10:22, 45] = CAR * 1000 + 3       # 12 px but one pixel wide: no box, mask only
    seg = Segmentation(label, instance, torch.zeros(1, 14, 32, 48))
    stub = type("Stub", (), {"classes": models.semantic.classes, "__call__": lambda self, image: seg})()
    intr = VKITTI_INTRINSICS.resized(48, 32)
    scene = derender(torch.rand(3, 32, 48), intr, Models(stub, models.geometric, models.textural, crop_size=32),
                     "auto", None, min_pixels=10)
    obj = scene.objects
    assert obj.instance_id.tolist() == [12001, 12003, 13007] and obj.template_id.tolist()[1:] == [-1, -1]
    assert obj.template_id[0] >= 0 and bool(obj.has_mask.all())
    assert torch.equal(obj.mask[2], instance[0] == 13007) and int(obj.mask[0].sum()) == 200
    assert scene.meta["proposals"] == "semantic" and scene.meta["with_geometry"] == 1
    assert int(scene.semantic[2, 44]) == ROAD and int(scene.semantic[15, 10]) == CAR  # dropped proposal: background


def test_bad_inputs_are_rejected(frame, models):
    record, f = frame
    with pytest.raises(ValueError, match="needs the frame's ground truth"):
        derender(f.image, f.intrinsics, models, "gt", None)
    with pytest.raises(ValueError, match="ground_truth is"):
        derender(f.image, f.intrinsics, models, "gt", ground_truth(record, (80, 32)))
    with pytest.raises(ValueError, match="needs a semantic model"):
        derender(f.image, f.intrinsics, Models(None, None, models.textural), "semantic", gt(record))
    with pytest.raises(ValueError, match="intrinsics are for"):
        derender(f.image[:, :32], f.intrinsics, models, "gt", gt(record))
    with pytest.raises(ValueError, match="proposals"):
        derender(f.image, f.intrinsics, models, "mask-rcnn", gt(record))
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        derender(f.image * 3, f.intrinsics, models, "gt", gt(record))


def test_render_and_edit_image(frame, models):
    record, f = frame
    result = edit_image(f.image, f.intrinsics, [], models, "gt", gt(record), compose="full", min_pixels=1,
                        appearance="generator")
    again = render(result.scene, models.textural)
    assert result.edited.shape == (3, *SIZE[::-1]) and 0 <= float(again.min()) and float(again.max()) <= 1
    torch.testing.assert_close(result.edited, again)  # no edit: the reconstruction
    assert result.edited_scene == result.scene
    victim = int(result.scene.objects.instance_id[0])
    deleted = edit_image(f.image, f.intrinsics, [Delete(victim)], models, "gt", gt(record), compose="full",
                         min_pixels=1, appearance="generator")
    assert victim not in deleted.edited_scene.objects.instance_id.tolist()
    assert victim not in deleted.maps.instance.unique().tolist()
    assert not torch.allclose(deleted.edited, again)
    torch.testing.assert_close(render_maps(deleted.maps, models.textural), deleted.edited)
    # Benchmark operations are resolved on the de-rendered scene (picks by projected centre).
    uv, _ = projected_centers(result.scene)
    op = BenchmarkOperation.modify(tuple(uv[0].tolist()), None, 1.0, 0.7)
    bench = edit_image(f.image, f.intrinsics, [op], models, "gt", gt(record), frame_size=None, min_pixels=1,
                       appearance="generator")
    row = bench.edited_scene.objects.index_of(victim)
    assert float(bench.edited_scene.objects.ry[row] - result.scene.objects.ry[0]) == pytest.approx(0.7, abs=1e-9)


def test_models_from_checkpoints_reads_the_run_crop_size(tmp_path, frame):
    run = tmp_path / "run"
    paths = write_checkpoints(run / "checkpoints")
    (run / "config.yaml").write_text("datamodule:\n  crop_size: 48\n  margin: 0.2\n")
    assert geometric_crop_settings(paths["geometric"]) == (48, 0.2)
    models = Models.from_checkpoints(**paths)
    assert (models.crop_size, models.margin) == (48, 0.2)
    assert models.semantic.net.num_classes == 14 and models.textural.spec.code_dim == 5
    assert Models.from_checkpoints(geometric=paths["geometric"], crop_size=40).crop_size == 40
    with pytest.raises(FileNotFoundError, match="textural checkpoint"):
        Models.from_checkpoints(textural=tmp_path / "missing.ckpt")
    record, f = frame
    scene = derender(f.image, f.intrinsics, models, "auto", gt(record), min_pixels=1)  # all three branches
    assert scene.meta["semantic"] == "branch" and scene.meta["proposals"] == "gt"
    assert torch.isfinite(render(scene, models.textural)).all()
    assert torch.equal(scene_maps(scene).instance, f.instances)  # unedited: the image's own layout


def test_refinement_ignores_the_objects_in_front(frame, models):
    """derender(refine=...) (the Cityscapes fit): a first pass orders the objects by predicted depth, the refined
    pass ignores, in each crop, the masks of the objects nearer than it."""
    from sdn3d.geometric.refine import RefineSettings

    record, f = frame
    spy = Spy(models.geometric.net)
    spied = Models(None, spy, models.textural, crop_size=32, margin=0.1)
    derender(f.image, f.intrinsics, spied, "gt", gt(record), min_pixels=1, refine=RefineSettings(iterations=1))
    first, refined = spy.calls
    assert first["refine"] is None and refined["refine"] is not None
    depth = spy.predict(first["crop"], first["mask"], first["box"], first["intrinsics"])["center"][:, 2]
    ignore = refined["ignore"][:, 0] > 0
    front = int(depth.argmin())
    assert not bool(ignore[front].any())  # nothing is in front of the nearest object
    others = ignore.sum((1, 2)) > 0
    assert bool(others.any()) and not bool(others[front])


@pytest.mark.parametrize("caller", ["edit_benchmark", "counterfactual"])
def test_the_benchmarks_read_the_geometric_crops_from_the_stored_frame(caller, frame, models, monkeypatch):
    """The editing benchmark's and the counterfactual benchmark's de-rendered sources get the frame as stored."""
    import sdn3d.evaluation.counterfactual as counterfactual
    import sdn3d.evaluation.edit_benchmark as edit_benchmark
    from sdn3d.data.records import load_rgb

    record, f = frame
    module = edit_benchmark if caller == "edit_benchmark" else counterfactual
    given = []
    monkeypatch.setattr(module, "derender", lambda *a, **k: given.append(k["photo"]) or "scene")
    if caller == "edit_benchmark":
        settings = edit_benchmark.BenchSettings(image_size=SIZE, proposals="gt")
        assert edit_benchmark._source_scene(f.image, f.intrinsics, record, models, settings) == "scene"
    else:
        settings = counterfactual.CounterfactualSettings(sources=("gt",))
        assert counterfactual._source_scene("gt", record, f.image, f.intrinsics, models, settings, SIZE) == "scene"
    stored = torch.from_numpy(load_rgb(record)).permute(2, 0, 1).float() / 255
    torch.testing.assert_close(given[0].image, stored)
    assert given[0].scale == (SIZE[0] / stored.shape[-1], SIZE[1] / stored.shape[-2])
