"""Objects a person names by a box (issue 31): GrabCut masks, the 3D fit on the road plane, derender with boxes,
the spec's ``objects:``, and ``sdn3d-edit`` on the real Virtual KITTI frame with random-weight branches."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
import torch
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d.box_masks import box_at_point, grabcut_masks, nearest_first, refine_with_silhouettes
from sdn3d.box_objects import BoxFit, MaskSource, box_grabcut
from sdn3d.cli.edit import main
from sdn3d.derender import BoxPrompts, GroundTruth, derender
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.spec import EditSpecError, box_prompts, parse_edit_spec
from sdn3d.errors import UserInputError
from sdn3d.geometric.fit import FitSettings, fit_to_masks, road_start
from sdn3d.image_ops import mask_boxes
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.bank import MeshBank
from sdn3d.models import Models
from sdn3d.render import RasterSettings, rasterize_meshes
from sdn3d.render.objects import pose_meshes

WORK = Intrinsics(725.0, 725.0, 620.5, 187.0, 1242, 375).resized(312, 96)
HEIGHT = 1.65


def _render(templates, dims, ry, location, intr=WORK):
    """``(ids (H, W), masks (N, H, W))`` of cars standing on the road, hard-rasterized."""
    dims = torch.tensor(dims, dtype=torch.float32)
    center = torch.tensor(location, dtype=torch.float32)
    center[:, 1] -= dims[:, 1] / 2
    verts, faces = pose_meshes(MeshBank.templates(), torch.tensor(templates), dims, torch.tensor(ry), center)
    n = len(templates)
    frags = rasterize_meshes(verts, faces, intr.matrix().float(), RasterSettings(intr.size),
                             mesh_to_image=torch.zeros(n, dtype=torch.long), batch_size=1)
    ids = frags.pix_to_mesh[0]
    return ids, torch.stack([ids == i for i in range(n)])


def _picture(masks: torch.Tensor, colors, seed: int = 0) -> torch.Tensor:
    """A ``(3, H, W)`` picture: textured grey road, each mask a flat colour with a little noise."""
    gen = torch.Generator().manual_seed(seed)
    h, w = masks.shape[-2:]
    image = 0.45 + 0.08 * torch.rand(3, h, w, generator=gen)
    for mask, color in zip(masks, colors, strict=True):
        image[:, mask] = torch.tensor(color)[:, None] + 0.03 * torch.rand(3, int(mask.sum()), generator=gen)
    return image.clamp(0, 1)


def test_nearest_first_orders_by_the_bottom_edge():
    assert nearest_first(torch.tensor([[0, 0, 10, 50], [0, 0, 20, 80], [0, 0, 30, 50]])).tolist() == [1, 2, 0]


def test_grabcut_finds_each_car_and_gives_every_pixel_one_owner():
    _, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.5, 1.8)], [-1.3, 0.4], [(-1.2, HEIGHT, 10.0),
                                                                                 (1.5, HEIGHT, 13.0)])
    image = _picture(masks, [(0.8, 0.1, 0.1), (0.1, 0.2, 0.7)])
    boxes = mask_boxes(masks).float()
    found = grabcut_masks(image, boxes)
    assert found.masks.shape == masks.shape and not bool(found.from_box.any())
    for got, true in zip(found.masks, masks, strict=True):
        iou = float((got & true).sum()) / float((got | true).sum())
        assert iou > 0.9
    assert int((found.masks.sum(0) > 1).sum()) == 0  # one owner per pixel
    # A uniform picture gives GrabCut nothing to learn: the box itself, said so.
    flat = grabcut_masks(torch.full((3, 96, 312), 0.5), torch.tensor([[100.0, 40.0, 140.0, 70.0]]))
    assert bool(flat.from_box[0]) and int(flat.masks[0].sum()) == 40 * 30


def test_grabcut_gives_an_overlap_to_the_nearer_box():
    image = torch.full((3, 60, 100), 0.5)
    image[:, 20:50, 10:60] = torch.tensor([0.9, 0.1, 0.1])[:, None, None]  # near: lower bottom edge
    image[:, 10:40, 40:90] = torch.tensor([0.1, 0.1, 0.9])[:, None, None]
    image[:, 20:50, 10:60] = torch.tensor([0.9, 0.1, 0.1])[:, None, None]
    found = grabcut_masks(image, torch.tensor([[40.0, 10.0, 90.0, 40.0], [10.0, 20.0, 60.0, 50.0]])).masks
    assert bool(found[1, 30, 50]) and not bool(found[0, 30, 50])  # the shared corner is the near car's
    assert bool(found[0, 15, 80])


def test_a_click_on_a_car_implies_its_box():
    """box_at_point: a click on each of two cars on the road gives that car's box (no weights: the road plane
    bounds the search, GrabCut finds the car); a click off the image is refused."""
    _, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.5, 1.8)], [-1.3, 0.4], [(-2.2, HEIGHT, 10.0),
                                                                                 (3.0, HEIGHT, 16.0)])
    image = _picture(masks, [(0.8, 0.1, 0.1), (0.1, 0.2, 0.7)])
    true_boxes = mask_boxes(masks).float()
    for mask, true in zip(masks, true_boxes, strict=True):
        rows, cols = torch.nonzero(mask, as_tuple=True)
        click = (float(cols.float().median()), float(rows.float().median()))
        box = box_at_point(image, click, WORK.fx, WORK.fy, WORK.cy, camera_height=HEIGHT)
        inter = (torch.minimum(box[2:], true[2:]) - torch.maximum(box[:2], true[:2])).clamp_min(0).prod()
        union = (box[2:] - box[:2]).prod() + (true[2:] - true[:2]).prod() - inter
        assert float(inter / union) > 0.85, (box.tolist(), true.tolist())
    with pytest.raises(ValueError, match="outside the 312x96 image"):
        box_at_point(image, (400.0, 10.0), WORK.fx, WORK.fy, WORK.cy)


def test_road_start_puts_the_car_where_its_bottom_edge_meets_the_road():
    intr = Intrinsics(725.0, 725.0, 620.5, 187.0, 1242, 375)
    start = road_start(torch.tensor([[600.0, 200.0, 640.0, 264.0]]), intr, 1.65, width=0.0)[0]
    v = intr.fy * start[1] / start[2] + intr.cy  # the bottom-centre point projects onto the bottom edge
    assert float(start[1]) == pytest.approx(1.65) and float(v) == pytest.approx(263.5, abs=1e-3)


def test_the_fit_recovers_a_car_on_the_road_from_its_silhouette():
    truth = {"templates": [3], "dims": [(4.2, 1.45, 1.75)], "ry": [0.6], "location": [(2.0, HEIGHT, 12.0)]}
    _, masks = _render(**truth)
    boxes = mask_boxes(masks).float()
    result = fit_to_masks(masks, boxes, WORK, start_ry=torch.tensor([0.8]))
    assert float(result.iou[0]) > 0.85
    assert float(result.location[0, 1]) == pytest.approx(HEIGHT)  # on the road plane
    assert float(result.location[0, 2]) == pytest.approx(12.0, rel=0.12)
    assert abs(math.remainder(float(result.ry[0]) - 0.6, 2 * math.pi)) < math.radians(20)
    # A start 90 degrees off is corrected: every start is tried and the silhouette decides clearly.
    side = fit_to_masks(masks, boxes, WORK, start_ry=torch.tensor([0.8 + math.pi / 2]))
    assert abs(math.remainder(float(side.ry[0]) - 0.6, 2 * math.pi)) < math.radians(20)
    # Front and back differ little: the yaw prior and the believed end (facing_tie) keep a reversed start's side;
    # without them the silhouette decides.
    kept = fit_to_masks(masks, boxes, WORK, start_ry=torch.tensor([0.8 + math.pi]))
    assert abs(math.remainder(float(kept.ry[0]) - 0.6 - math.pi, 2 * math.pi)) < math.radians(20)
    free = fit_to_masks(masks, boxes, WORK, start_ry=torch.tensor([0.8 + math.pi]),
                        settings=FitSettings(yaw_reg=0.0, facing_tie=0.0))
    assert abs(math.remainder(float(free.ry[0]) - 0.6, 2 * math.pi)) < math.radians(20)
    with pytest.raises(ValueError, match="keep"):
        FitSettings(keep=0)


@pytest.fixture(params=[1, 2], ids=["threads=1", "threads=2"])
def torch_threads(request):
    """A fitted-value test runs under one and two torch threads (a fit's sums, and so its result, may differ with
    the thread count and the machine: its margins hold under both), restored afterwards. Only the occluder test
    takes it: two threads cost ten times one on a loaded 2-core machine, and the other fits' margins are wide."""
    previous = torch.get_num_threads()
    torch.set_num_threads(request.param)
    yield request.param
    torch.set_num_threads(previous)


def _silhouette(fit, row: int = 0) -> torch.Tensor:
    """The ``(H, W)`` silhouette of a fitted car (its template, size, yaw and place; no FFD) in :data:`WORK`."""
    return _render([int(fit.template[row])], [tuple(fit.dims[row].tolist())], [float(fit.ry[row])],
                   [tuple(fit.location[row].tolist())])[1][0]


def _iou(a: torch.Tensor, b: torch.Tensor) -> float:
    return float((a & b).sum()) / max(float((a | b).sum()), 1.0)


def test_an_occluder_is_not_charged_to_the_car_behind_it(torch_threads):
    """Three fifths of the far car is hidden by the near one: ignoring the near car's pixels, the fit finds the whole
    car, as big as the car fitted alone; charged for them, it shrinks and shifts the car to the visible sliver.

    Tested with margins the numerics cannot cross (issue 42: the charged fit's width was 1.3196 m against a 1.3 m
    bound): the fitted silhouettes against the whole car's (observed IoU 0.86 ignored, 0.20 charged, under 1 and 2
    threads), the ignored fit's size against the car fitted alone (each dimension within 5 %), never a hair-thin
    constant."""
    _, masks = _render([0, 2], [(4.0, 1.5, 1.7), (4.0, 1.5, 1.7)], [-1.5, -1.5], [(0.3, HEIGHT, 9.0),
                                                                                   (1.5, HEIGHT, 14.0)])
    _, alone = _render([2], [(4.0, 1.5, 1.7)], [-1.5], [(1.5, HEIGHT, 14.0)])
    box = mask_boxes(alone).float()  # the person's box is around the whole car
    plain = FitSettings(template_size_reg=0.0)  # the silhouette alone decides the size (the template's size pulls)
    ignored = fit_to_masks(masks[1:], box, WORK, ignore=masks[:1], start_ry=torch.tensor([-1.5]), settings=plain)
    charged = fit_to_masks(masks[1:], box, WORK, start_ry=torch.tensor([-1.5]), settings=plain)
    whole = fit_to_masks(alone, box, WORK, start_ry=torch.tensor([-1.5]), settings=plain)  # nothing hides it
    assert float(ignored.iou[0]) > 0.8 and float(charged.iou[0]) < float(ignored.iou[0]) - 0.2  # 0.91, 0.49
    # The shapes: ignoring the occluder covers the whole car, charging it does not (observed 0.86 and 0.20 with the
    # session-3 search, 0.48 for the charged fit with the pruned search of issue 40's cost: margins > 0.1 and 0.25)
    whole_ignored, whole_charged = _iou(_silhouette(ignored), alone[0]), _iou(_silhouette(charged), alone[0])
    assert whole_ignored > 0.75 and whole_charged < whole_ignored - 0.25, (whole_ignored, whole_charged)
    # The size: what the occluder hides costs the car nothing (fitted alone: 3.70 x 1.48 x 1.55 m, ignored: within
    # 6 %); charged for it, the car is made smaller (volume 5.9 against 8.1 m^3; 7.0 against 8.1 with
    # FitSettings.ffd_step 0.1, whose FFD moves less: the bound is 0.9)
    assert torch.allclose(ignored.dims[0], whole.dims[0], rtol=0.15), (ignored.dims, whole.dims)
    assert float(charged.dims[0].prod()) < 0.9 * float(ignored.dims[0].prod())
    assert float(ignored.location[0, 2]) == pytest.approx(14.0, rel=0.1)  # 14.46 m


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def test_derender_adds_box_objects_and_records_where_they_came_from(ckpts):
    _, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.5, 1.8)], [-1.3, 0.4], [(-1.2, HEIGHT, 10.0),
                                                                                 (1.5, HEIGHT, 13.0)])
    image = _picture(masks, [(0.8, 0.1, 0.1), (0.1, 0.2, 0.7)])
    models = Models.from_checkpoints(geometric=ckpts["geometric"], crop_size=32)
    boxes = BoxPrompts(mask_boxes(masks).float(), ("Car", "van"))
    scene = derender(image, WORK, models, "boxes", boxes=boxes, classes="vkitti")
    assert scene.objects.instance_id.tolist() == [12001, 13001]  # the next free number of each class
    assert bool(scene.objects.has_geometry.all()) and scene.meta["proposals"] == "boxes"
    for record, row in zip(scene.meta["boxes"], (0, 1), strict=True):  # typed records (BoxFit)
        assert record.mask_source is MaskSource.GRABCUT and record.mask_refined
        assert record.iou > 0.8 and not record.poor and record.pose_source is not None
        assert record.mask_pixels == int(scene.objects.mask[row].sum())
        assert record.instance_id == int(scene.objects.instance_id[row])
        shown = record.to_json()  # as scene.json and edit.json say it
        assert shown["mask"] == "grabcut, then again seeded by its fitted 3D shape"
        assert shown["pose"].startswith("fitted to the mask") and shown["fit_iou"] == round(record.iou, 4)
        # the hypothesis that won is on the record (issue 40): the prediction, its flip or a search start
        assert record.hypothesis is not None and shown["hypothesis"] == record.hypothesis and record.fit_note is None
        # read back from a scene file: the rounded figures (the pixels at the fit are only kept where there was none)
        assert BoxFit.from_json(shown, scene.meta["min_pixels"]) == dataclasses.replace(
            record, box=tuple(round(v, 2) for v in record.box), iou=shown["fit_iou"], fit_pixels=record.mask_pixels)
    # The second GrabCut, seeded by the fitted shape, keeps the true masks (GrabCut alone finds these flat-coloured
    # cars exactly; where it misses a road-grey wheel, the seed brings it back: refine_with_silhouettes' example).
    once = derender(image, WORK, models, "boxes", boxes=dataclasses.replace(boxes, refine_masks=False),
                    classes="vkitti")
    assert [r.to_json()["mask"] for r in once.meta["boxes"]] == ["grabcut", "grabcut"]

    def iou(a: torch.Tensor, b: torch.Tensor) -> float:
        return float((a & b).sum() / (a | b).sum())

    for row in (0, 1):
        assert iou(scene.objects.mask[row], masks[row]) > 0.95 and iou(once.objects.mask[row], masks[row]) > 0.95
    assert float(scene.objects.location[0, 1]) == pytest.approx(HEIGHT)
    # the box named a van is drawn with a box-shaped template (the van, minibus or bus: CLASS_TEMPLATES), though its
    # silhouette is an SUV's
    assert int(scene.objects.template_id[1]) in (5, 6, 7)
    # Given masks replace GrabCut's; the nearer object keeps a shared pixel.
    both = masks.clone()
    both[1] |= masks[0]
    given = derender(image, WORK, models, "boxes", classes="vkitti",
                     boxes=BoxPrompts(mask_boxes(masks).float(), ("Car", "Car"), masks=both))
    assert given.meta["boxes"][0].mask_source is MaskSource.GIVEN and int((given.objects.mask.sum(0) > 1).sum()) == 0
    # With a semantic branch its object probability may seed GrabCut (the record says so).
    seeded = derender(image, WORK, Models.from_checkpoints(ckpts["semantic"], ckpts["geometric"], crop_size=32),
                      "boxes", boxes=dataclasses.replace(boxes, prior=True))
    assert seeded.meta["semantic"] == "branch"
    assert all(r.mask_source in (MaskSource.GRABCUT_PRIOR, MaskSource.WHOLE_BOX) for r in seeded.meta["boxes"])
    with pytest.raises(UserInputError, match="not an object class"):
        derender(image, WORK, models, "boxes", classes="vkitti", boxes=BoxPrompts(boxes.boxes, ("Road", "Car")))
    with pytest.raises(UserInputError, match="needs objects given by a box"):
        derender(image, WORK, models, "boxes", classes="vkitti")


def test_spec_objects_parse_check_and_map_to_the_working_image():
    spec = parse_edit_spec({"objects": [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305]}]})
    assert len(spec) == 0 and [o.class_ for o in spec.objects] == ["Car", "Car"]
    frame = PixelFrame((1242, 375), (624, 192))
    prompts = box_prompts(spec, (624, 192), frame)
    x0, y0, x1, y1 = prompts.boxes[0].tolist()
    assert x0 == pytest.approx(466 * 624 / 1242, abs=1e-3) and y1 == pytest.approx(333 * 192 / 375, abs=1e-3)
    with_ops = parse_edit_spec({"objects": [{"box": [1, 1, 9, 9]}], "ops": [{"op": "delete", "at": [5, 5]}]})
    assert len(with_ops) == 1 and len(with_ops.objects) == 1
    for bad, match in (({"box": [10, 10, 11, 30]}, "x1 >= x0"), ({"box": [1, 2, 3]}, r"\[x0, y0, x1, y1\]"),
                       ({"box": [0, 0, "a", 9]}, "must be a number"), ({"box": [0, 0, 9, 9], "size": 3}, "unknown"),
                       ({"box": [0, 0, 9, 9], "class": [1]}, "class name")):
        with pytest.raises(EditSpecError, match=match):
            parse_edit_spec({"objects": [bad]})
    with pytest.raises(EditSpecError, match="outside the working image"):
        box_prompts(parse_edit_spec({"objects": [{"box": [2000, 10, 2100, 50]}]}), (624, 192), frame)


def _spec(path, ops: str = "") -> str:
    path.write_text("objects:\n  - {box: [466, 203, 666, 333], class: Car}\n"
                    "  - {box: [704, 194, 917, 305], class: Car}\n" + (f"ops:\n{ops}" if ops else ""))
    return str(path)


REAL = Path(__file__).resolve().parent / "data" / "0006_30-deg-right_00043.png"  # a real Virtual KITTI frame


def _cli(ckpts, out, edits, *extra):
    # threads=1 (as test_box_refusal's): two threads took these sdn3d-edit calls 3x longer on a loaded 2-core machine;
    # the torch_threads fixture's test runs a fit under two threads
    return main([f"input.image={REAL}", f"edits={edits}", "proposals=boxes",
                 f"checkpoints.geometric={ckpts['geometric']}", f"checkpoints.textural={ckpts['textural']}",
                 "geometric.crop_size=32", "image_size=[312,96]", f"output_dir={out}", "threads=1", *extra])


def test_sdn3d_edit_lists_and_edits_box_objects_of_a_real_photo(ckpts, tmp_path, capsys):
    """The real Virtual KITTI frame, no semantic checkpoint: boxes around the two near cars are enough."""
    assert _cli(ckpts, tmp_path / "list", _spec(tmp_path / "list.yaml")) == 0
    printed = capsys.readouterr().out
    assert "fit IoU" in printed and "from a box" in printed
    listing = json.loads((tmp_path / "list" / "objects.json").read_text())
    assert [r["id"] for r in listing["objects"]] == [12001, 12002]
    assert all(r["fit_iou"] > 0.7 and r["given_box"] for r in listing["objects"])
    assert Image.open(tmp_path / "list" / "objects.png").size[0] == 1242

    edits = _spec(tmp_path / "ops.yaml", "  - {op: rotate, at: [565, 280], ry_deg: 45}\n"
                                         "  - {op: delete, at: [810, 260]}\n")
    assert _cli(ckpts, tmp_path / "out", edits) == 0
    summary = json.loads((tmp_path / "out" / "edit.json").read_text())
    assert summary["proposals"]["masks"] == "boxes" and summary["proposals"]["semantics"] == "none"
    origins = {o["id"]: o for o in summary["edited_objects"]}
    assert set(origins) == {12001, 12002}
    assert origins[12001]["mask"] == ("in the box [466.0, 203.0, 666.0, 333.0] (input pixels): grabcut, then again "
                                      "seeded by its fitted 3D shape")
    assert origins[12001]["pose"].startswith("fitted to the mask") and origins[12001]["fit_iou"] > 0.7
    assert [b["input_box"] for b in summary["boxes"]] == [[466.0, 203.0, 666.0, 333.0], [704.0, 194.0, 917.0, 305.0]]
    before = np.asarray(Image.open(REAL).convert("RGB")).astype(int)
    after = np.asarray(Image.open(tmp_path / "out" / "edited.png")).astype(int)
    changed = np.abs(after - before).max(2) > 0
    assert changed[203:333, 466:666].mean() > 0.3 and changed[194:305, 704:917].mean() > 0.5
    assert not changed[:150].any() and not changed[:, :300].any()  # sky, trees and the left road untouched


def test_a_poor_fit_is_flagged_before_the_edit(ckpts, tmp_path, capsys):
    edits = _spec(tmp_path / "ops.yaml", "  - {op: delete, at: [810, 260]}\n")
    assert _cli(ckpts, tmp_path / "out", edits, "box_objects.fit.poor_iou=0.999") == 0
    err = capsys.readouterr().err
    assert "box object 12001" in err and "matches its mask poorly" in err
    summary = json.loads((tmp_path / "out" / "edit.json").read_text())
    assert any("poorly" in w for w in summary["warnings"])


def test_box_settings_and_missing_objects_are_refused(ckpts, tmp_path, capsys):
    spec = tmp_path / "ops.yaml"
    spec.write_text("- {op: delete, at: [810, 260]}\n")
    assert _cli(ckpts, tmp_path / "a", str(spec)) == 2
    assert "proposals=boxes takes the objects" in capsys.readouterr().err
    assert _cli(ckpts, tmp_path / "b", _spec(tmp_path / "l.yaml"), "box_objects.fit.keep=0") == 2
    assert "box_objects.fit" in capsys.readouterr().err
    assert _cli(ckpts, tmp_path / "c", _spec(tmp_path / "l.yaml"), "box_objects.refine_masks=maybe") == 2
    assert "box_objects.refine_masks must be true or false" in capsys.readouterr().err
    assert not any((tmp_path / d).exists() for d in "abc")


def test_the_second_grabcut_can_be_switched_off(ckpts, tmp_path):
    assert _cli(ckpts, tmp_path / "once", _spec(tmp_path / "l.yaml"), "box_objects.refine_masks=false") == 0
    listing = json.loads((tmp_path / "once" / "objects.json").read_text())
    assert [r["mask_from"] for r in listing["objects"]] == ["grabcut", "grabcut"]


def test_grabcut_masks_do_not_depend_on_what_ran_before_in_the_thread(real_vkitti_frame):
    """OpenCV's per-thread generator is put back before each GrabCut: the same boxes give the same masks after other
    random draws of OpenCV in this thread (a long-running editor gives sdn3d-edit's masks). Without the reset the
    real frame's masks differ from call to call."""
    import cv2

    image = np.asarray(Image.open(real_vkitti_frame).convert("RGB"))
    boxes = torch.tensor([[466.0, 203.0, 666.0, 333.0], [704.0, 194.0, 917.0, 305.0]])
    first = grabcut_masks(image, boxes).masks
    noise = np.zeros((64, 64))
    for _ in range(3):
        cv2.randu(noise, 0, 1)
        assert torch.equal(grabcut_masks(image, boxes).masks, first)


def test_the_second_grabcut_takes_what_the_fitted_shape_shows_and_nothing_it_may_not():
    """refine_with_silhouettes: a road-grey lower body that GrabCut left out comes back where the fitted shape covers
    it; a row not to refine keeps its first mask; another object's pixels are never taken; shapes are checked."""
    image = torch.full((3, 60, 100), 0.5)
    image[:, 10:40, 10:40] = torch.tensor([0.9, 0.2, 0.2])[:, None, None]  # a red car, its lower body road-grey
    image[:, 32:40, 10:40] = 0.5
    image[:, 12:36, 60:90] = torch.tensor([0.2, 0.3, 0.9])[:, None, None]  # a blue one
    boxes = torch.tensor([[10.0, 10.0, 40.0, 40.0], [60.0, 12.0, 90.0, 36.0]])
    first = grabcut_masks(image, boxes).masks
    assert int(first[0, 33:40].sum()) == 0  # GrabCut alone: the grey part is road
    drawn = torch.zeros_like(first)
    drawn[0, 10:40, 10:40] = True
    drawn[1, 12:36, 60:90] = True
    again = refine_with_silhouettes(image, boxes, first, drawn)
    assert int(again[0, 33:39, 11:39].sum()) == 6 * 28 and torch.equal(again[1], first[1])
    kept = refine_with_silhouettes(image, boxes, first, drawn, refine=torch.tensor([False, True]))
    assert torch.equal(kept[0], first[0])
    others = torch.zeros(60, 100, dtype=torch.bool)
    others[30:40, 10:20] = True  # e.g. a semantic proposal in front
    guarded = refine_with_silhouettes(image, boxes, first, drawn, others=others)
    assert not bool((guarded[0] & others).any()) and int(guarded[0, 33:39, 21:39].sum()) == 6 * 18
    with pytest.raises(ValueError, match="silhouettes must be"):
        refine_with_silhouettes(image, boxes, first, drawn[:1])


def test_the_fit_pulls_the_size_towards_the_drawn_templates_typical_size():
    """template_size_reg compares the size with TEMPLATE_DIMENSIONS of the template drawn; a bank of other meshes has
    no typical size, and the fit then runs without the term."""
    from sdn3d.geometric.fit import _typical_log_dims
    from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS, TEMPLATE_NAMES

    typical = _typical_log_dims(MeshBank.templates())
    assert torch.allclose(typical.exp(), torch.tensor([TEMPLATE_DIMENSIONS[n] for n in TEMPLATE_NAMES]))
    assert _typical_log_dims(MeshBank.vehicle_shapes()) is None
    with pytest.raises(ValueError, match="template_size_reg"):
        FitSettings(template_size_reg=-1.0)
    # A 4 m car seen from behind, fitted with the bus and the sedan only: the bus's 12 m keeps it a sedan.
    _, masks = _render([0], [(4.6, 1.45, 1.8)], [-math.pi / 2], [(0.5, HEIGHT, 11.0)])
    bank = MeshBank.templates()
    two = MeshBank.from_arrays([bank.verts[i, :int(bank.num_verts[i])].numpy() for i in (0, 7)],
                               [bank.faces[i, :int(bank.num_faces[i])].numpy() for i in (0, 7)], ["sedan", "bus"])
    fitted = fit_to_masks(masks, mask_boxes(masks).float(), WORK, bank=two, start_ry=torch.tensor([-math.pi / 2]))
    assert int(fitted.template[0]) == 0 and float(fitted.iou[0]) > 0.8


def test_a_box_whose_mask_was_too_thin_to_fit_says_so_by_its_id():
    """issue 40: a mask too small or thin keeps the branch's prediction; the warning names the object, not an index."""
    from sdn3d.editing.session import fit_warnings

    fit = BoxFit(12003, (1.0, 2.0, 30.0, 4.0), MaskSource.GRABCUT, False, 70, None, 0.0, True, 70, 64,
                 "not fitted (prediction kept)", "its mask is 2 px thin (< 3): not fitted, the geometric branch's "
                 "prediction kept")
    record = {**fit.to_json(), "input_box": [2.0, 4.0, 60.0, 8.0]}
    assert record["hypothesis"] == "not fitted (prediction kept)"
    assert BoxFit.from_json(record, 64) == fit
    (line,) = fit_warnings([record], 0.7)
    assert line.startswith("box object 12003 (box [2.0, 4.0, 60.0, 8.0]): its mask is 2 px thin")


def test_grabcut_without_a_prior_runs_beside_the_semantic_branch(ckpts, monkeypatch):
    """Without a prior GrabCut needs no semantics: derender runs it on a second thread while the semantic branch runs
    (issue 40: the call's second core), and the scene is the one GrabCut run after the branch gives."""
    import threading

    import sdn3d.derender as derender_module

    _, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.5, 1.8)], [-1.3, 0.4], [(-1.2, HEIGHT, 10.0),
                                                                                 (1.5, HEIGHT, 13.0)])
    image = _picture(masks, [(0.8, 0.1, 0.1), (0.1, 0.2, 0.7)])
    models = Models.from_checkpoints(ckpts["semantic"], ckpts["geometric"], crop_size=32)
    boxes = BoxPrompts(mask_boxes(masks).float(), ("Car", "van"), refine_masks=False)
    where: dict[str, int] = {}
    grabcut, semantics = derender_module.box_grabcut, derender_module._semantics_and_instances

    def grabcut_here(*args):
        where["grabcut"] = threading.get_ident()
        return grabcut(*args)

    def semantics_here(*args):
        where["semantic"] = threading.get_ident()
        return semantics(*args)

    monkeypatch.setattr(derender_module, "box_grabcut", grabcut_here)
    monkeypatch.setattr(derender_module, "_semantics_and_instances", semantics_here)
    beside = derender(image, WORK, models, "boxes", boxes=boxes)
    assert where["semantic"] == threading.get_ident() != where["grabcut"]
    assert [r.mask_source for r in beside.meta["boxes"]] == [MaskSource.GRABCUT] * 2
    monkeypatch.setattr(derender_module, "box_grabcut", lambda *args: None)  # add_box_objects runs GrabCut itself
    after = derender(image, WORK, models, "boxes", boxes=boxes)
    assert torch.equal(beside.objects.mask, after.objects.mask) and beside.meta["boxes"] == after.meta["boxes"]
    assert box_grabcut(image, dataclasses.replace(boxes, prior=True)) is None  # the prior needs the branch first


@pytest.mark.fits
def test_box_objects_are_drawn_towards_the_roads_axis_with_the_sharp_outlines_weight(ckpts, monkeypatch):
    """Issue 40, session 39: a box object's fit reads the road's axis where it stands (the lines around it,
    :func:`sdn3d.road_heading.road_axes`) with ``lane_reg``, whether it is fitted alone or with the proposals (one
    :func:`~sdn3d.geometric.fit.fit_many` call); with ``lane_reg`` 0 it reads none."""
    import sdn3d.geometric.fit as F
    from sdn3d.road_heading import road_axes

    _, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.5, 1.8)], [-1.3, 0.4], [(-1.2, HEIGHT, 10.0),
                                                                                 (1.5, HEIGHT, 13.0)])
    image = _picture(masks, [(0.8, 0.1, 0.1), (0.1, 0.2, 0.7)])
    for bottom_x in (-60.0, 60.0, 250.0, 370.0):  # lane lines meeting on the horizon straight ahead
        for t in torch.linspace(0, 1, 400):
            x, y = round(WORK.cx + t.item() * (bottom_x - WORK.cx)), round(WORK.cy + t.item() * (95 - WORK.cy))
            if 0 <= x < WORK.width and y > WORK.cy + 2 and not bool(masks[:, y, x].any()):
                image[:, y, x] = 0.95
    models = Models.from_checkpoints(geometric=ckpts["geometric"], crop_size=32)
    small = FitSettings(coarse_steps=3, fine_steps=2, coarse_size=16, fine_size=24, coarse_survivors=0, parts=1,
                        lane_reg=0.03)
    asked = []
    real = F.fit_many

    def spy(requests, intr, **kwargs):
        asked.append(requests)
        return real(requests, intr, **kwargs)

    monkeypatch.setattr(F, "fit_many", spy)
    want = road_axes(image, WORK.matrix(), masks, masks.any(0))
    assert bool(torch.isfinite(want).all())  # the lines tell the axis at both cars
    boxes = BoxPrompts(mask_boxes(masks).float(), ("Car", "Car"), small, masks=masks, refine_masks=False)
    derender(image, WORK, models, "boxes", boxes=boxes, classes="vkitti")
    scene = derender(image, WORK, models, "boxes", boxes=boxes, classes="vkitti")
    (request,) = asked.pop()
    torch.testing.assert_close(request.road_ry, want)
    assert request.lane_reg is None  # the settings' lane_reg: a sharp outline's weight
    records = scene.meta["boxes"]  # each record names the axis its fit was drawn towards, and reads back
    assert [r.road_axis_deg for r in records] == pytest.approx(torch.rad2deg(want).tolist())
    assert [BoxFit.from_json(r.to_json(), 0).road_axis_deg for r in records] == pytest.approx(
        [round(r.road_axis_deg, 2) for r in records])
    unpulled = dataclasses.replace(boxes, fit=dataclasses.replace(small, lane_reg=0.0))
    scene = derender(image, WORK, models, "boxes", boxes=unpulled, classes="vkitti")
    assert asked.pop()[0].road_ry is None
    assert all(r.road_axis_deg is None and "road_axis_deg" not in r.to_json() for r in scene.meta["boxes"])
    # Fitted with the ground truth's masks in one call (the oracle's objects ask with lane_reg too): the box object's
    # request and record carry its axis all the same.
    instances = torch.zeros(masks.shape[1:], dtype=torch.long)
    instances[masks[0]] = 12001
    semantic = torch.where(instances > 0, torch.full_like(instances, 12), torch.full_like(instances, 1))
    gt = GroundTruth("synthetic", "vkitti", semantic, instances)
    one = BoxPrompts(mask_boxes(masks[1:]).float(), ("Car",), small, masks=masks[1:], refine_masks=False)
    scene = derender(image, WORK, models, "gt", gt, boxes=one, fit=small, classes="vkitti")
    (truths, box_req) = asked.pop()
    assert truths.lane_reg == small.lane_reg and box_req.lane_reg is None
    torch.testing.assert_close(box_req.road_ry, want[1:])
    assert scene.meta["boxes"][0].road_axis_deg == pytest.approx(float(torch.rad2deg(want[1])))
