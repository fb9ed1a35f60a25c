"""``sdn3d-edit`` on a user's picture: the camera is never guessed silently, the resize keeps the aspect ratio
(scale, then a central crop, recorded in ``edit.json``), and edit-spec pixels are the input image's."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import torch
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d.cli.edit import main
from sdn3d.data import vkitti1
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.editing.apply import EditError
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.spec import EditSpec, load_edit_spec, parse_edit_spec, resolve_ops
from sdn3d.math3d.camera import Intrinsics

FRAME = "0001/clone/00004"
SKY = "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}"
CAMERA = {"fx": 300.0, "fy": 310.0, "u0": 130.0, "v0": 60.0}  # of the 256x128 picture below


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


@pytest.fixture
def picture(tiny_synth, tmp_path):
    """A 256x128 street picture (aspect 2: neither Virtual KITTI's 3.31 nor the 160x64 working size's 2.5)."""
    rgb = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    path = tmp_path / "street.png"
    Image.fromarray(np.ascontiguousarray(rgb)).resize((256, 128)).save(path)
    (tmp_path / "ops.yaml").write_text(SKY)
    return path


def _args(ckpts, image, out, *extra):
    return [f"input.image={image}", "image_size=[160,64]", f"edits={image.parent / 'ops.yaml'}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", f"output_dir={out}",
            *extra]


def _camera_json(path, intrinsic):
    extrinsic = {"baseline": 0.2, "pitch": 0.04, "roll": 0.0, "x": 1.7, "y": 0.1, "yaw": 0.0, "z": 1.2}
    path.write_text(json.dumps({"extrinsic": extrinsic, "intrinsic": intrinsic}, indent=4))
    return path


def test_unknown_camera_is_refused_naming_what_to_pass(ckpts, picture, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(_args(ckpts, picture, out)) == 2
    err = capsys.readouterr().err
    assert err.startswith("sdn3d-edit: error: input.image is 256x128, not Virtual KITTI's 1242x375") and err.count(
        "\n") == 1
    assert "input.intrinsics=" in err and "input.camera=" in err and not out.exists()
    assert main(_args(ckpts, picture, out, "input.intrinsics={fx:1,fy:1,cx:0,cy:0}",
                      f"input.camera={_camera_json(tmp_path / 'c.json', CAMERA)}")) == 2
    assert "not both" in capsys.readouterr().err
    assert main(_args(ckpts, picture, out, f"input.camera={_camera_json(tmp_path / 'bad.json', {'fx': 1})}")) == 2
    assert capsys.readouterr().err.startswith("sdn3d-edit: error: input.camera:") and not out.exists()
    assert main(_args(ckpts, picture, out, "input.intrinsics={fx:1,fy:1,cx:0,cy:0,width:100,height:50}")) == 2
    assert "are for 100x50 but the image is 256x128" in capsys.readouterr().err


def _expected(intr: Intrinsics) -> Intrinsics:
    """256x128 -> 160x64 keeping the aspect: scale max(160/256, 64/128) = 0.625 to 160x80, then the central
    160x64 (rows 8..71)."""
    return intr.resized(160, 80).cropped(0, 8, 160, 64)


def test_given_intrinsics_run_with_the_aspect_kept(ckpts, picture, tmp_path):
    out = tmp_path / "out"
    assert main(_args(ckpts, picture, out, "input.intrinsics={fx:300,fy:310,cx:127.5,cy:63.5}")) == 0
    summary = json.loads((out / "edit.json").read_text())
    want = _expected(Intrinsics(300, 310, 127.5, 63.5, 256, 128))
    assert summary["intrinsics"] == pytest.approx(want.to_dict())
    transform = summary["input_transform"]
    assert transform["input_size"] == [256, 128] and transform["working_size"] == [160, 64]
    assert transform["mode"] == "scale_crop" and transform["scaled_size"] == [160, 80]
    assert transform["scale"] == [0.625, 0.625] and transform["crop_offset"] == [0, 8]
    assert np.asarray(Image.open(out / "edited.png")).shape == (128, 256, 3)  # the input's size (photo)


def test_cityscapes_camera_json_runs_and_is_recorded(ckpts, picture, tmp_path):
    out = tmp_path / "out"
    camera = _camera_json(tmp_path / "aachen_000000_000019_camera.json", CAMERA)
    assert main(_args(ckpts, picture, out, f"input.camera={camera}")) == 0
    summary = json.loads((out / "edit.json").read_text())
    # The camera looks 0.04 rad down: its level virtual camera has the pitch folded into cy (issue 40).
    level = Intrinsics(CAMERA["fx"], CAMERA["fy"], CAMERA["u0"], CAMERA["v0"] - CAMERA["fy"] * math.tan(0.04), 256, 128)
    assert summary["intrinsics"] == pytest.approx(_expected(level).to_dict())
    assert summary["camera"] == {"camera_height": 1.2, "camera_height_from": "input.camera", "pitch": 0.04,
                                 "roll": 0.0, "roll_ignored": False, "pose_from": "input.camera"}


def test_a_virtual_kitti_shaped_image_needs_no_camera(ckpts, tiny_synth, tmp_path):
    rgb = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    Image.fromarray(np.ascontiguousarray(rgb)).resize((414, 125)).save(tmp_path / "vk.png")  # 1242x375 / 3
    (tmp_path / "ops.yaml").write_text(SKY)
    out = tmp_path / "out"
    assert main(_args(ckpts, tmp_path / "vk.png", out, "image_size=[624,192]")) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["input_transform"]["mode"] == "resize"  # 3.31 vs 3.25: within 2 %, resized as in training
    assert summary["intrinsics"]["fx"] == pytest.approx(725 * 624 / 1242)


def test_the_transform_maps_points_as_the_intrinsics():
    frame = PixelFrame((256, 128), (160, 64), (160, 80), (0, 8))
    intr = Intrinsics(300, 310, 127.5, 63.5, 256, 128)
    work = _expected(intr)
    assert frame.to_working((intr.cx, intr.cy)) == pytest.approx((work.cx, work.cy))
    # a 3D point projects to the mapped pixel
    x, y, z = 1.3, -0.4, 9.0
    uv_in = (intr.fx * x / z + intr.cx, intr.fy * y / z + intr.cy)
    assert frame.to_working(uv_in) == pytest.approx((work.fx * x / z + work.cx, work.fy * y / z + work.cy))
    assert frame.to_input(frame.to_working((17.0, 101.0))) == pytest.approx((17.0, 101.0))
    assert frame.to_working((-0.5, 15.5)) == pytest.approx((-0.5, 1.5))  # the crop's top 8 working rows are gone


# -- edit-spec pixels are the input image's -----------------------------------------------------------


@pytest.fixture(scope="module")
def scene(tiny_synth):
    """Frame 00004 worked on at 80x32 (stored at 160x64: input pixels are 2x the working pixels)."""
    return scene_from_frame(vkitti1.read_frames(tiny_synth)[4], (80, 32))


def _inside_pixel(scene, row):
    ys, xs = scene.objects.mask[row].nonzero(as_tuple=True)
    return float(xs[len(xs) // 2]), float(ys[len(ys) // 2])


def test_input_pixels_pick_what_working_pixels_picked(scene):
    frame = PixelFrame((160, 64), (80, 32))
    for row in range(len(scene.objects)):
        x, y = _inside_pixel(scene, row)
        before = resolve_ops(parse_edit_spec([{"op": "delete", "at": [x, y]}]), scene)  # working pixels, no frame
        u, v = frame.to_input((x, y))  # (x + 0.5) * 2 - 0.5
        assert (u, v) == (2 * x + 0.5, 2 * y + 0.5)
        now = resolve_ops(parse_edit_spec([{"op": "delete", "at": [u, v]}]), scene, frame=frame)
        sized = resolve_ops(parse_edit_spec({"frame_size": [80, 32], "ops": [{"op": "delete", "at": [x, y]}]}),
                            scene, frame=frame)  # frame_size still overrides
        assert now == before == sized


def test_input_pixels_through_a_crop(scene):
    frame = PixelFrame((200, 64), (80, 32), (100, 32), (10, 0))  # scale 0.5, 10 columns cropped each side
    for row in range(len(scene.objects)):
        x, y = _inside_pixel(scene, row)
        before = resolve_ops(parse_edit_spec([{"op": "delete", "at": [x, y]}]), scene)
        u, v = frame.to_input((x, y))
        assert (u, v) == pytest.approx(((x + 10 + 0.5) * 2 - 0.5, (y + 0.5) * 2 - 0.5))
        assert resolve_ops(parse_edit_spec([{"op": "delete", "at": [u, v]}]), scene, frame=frame) == before
    iid = int(scene.objects.instance_id[scene.objects.has_geometry][0])
    spec = parse_edit_spec([{"op": "move", "id": iid, "to": [5.04, 20]}])  # in the input, cropped away
    with pytest.raises(EditError, match=re.escape("'to' point [5.0, 20.0] lies outside the part of the 200x64 "
                                                  "frame the working image keeps (x 19.5..179.5, y -0.5..63.5)")):
        resolve_ops(spec, scene, frame=frame)


def test_errors_show_the_users_pixels(scene):
    frame = PixelFrame((160, 64), (80, 32))
    iid = int(scene.objects.instance_id[scene.objects.has_geometry][0])
    with pytest.raises(EditError, match=re.escape("'to' point [170.0, 20.0] lies outside the 160x64 frame")):
        resolve_ops(parse_edit_spec([{"op": "move", "id": iid, "to": [170, 20]}]), scene, frame=frame)
    free = _free_pixel(scene)
    with pytest.raises(EditError, match=r"no object at \[\d+\.\d, \d+\.\d\]: no mask or listed box holds it, and "
                                        r"no centre is within 0.001 px \(working size\); the nearest: \d+ \(\d+ px"):
        resolve_ops(parse_edit_spec([{"op": "delete", "at": [2 * free[1] + 0.5, 2 * free[0] + 0.5]}]), scene,
                    pick_radius=0.001, frame=frame)


def _free_pixel(scene) -> list[int]:
    """``[row, column]`` of a working pixel under no object's mask and outside every object's mask box."""
    from sdn3d.image_ops import mask_boxes

    free = scene.objects.mask.sum(0) == 0
    for x0, y0, x1, y1 in mask_boxes(scene.objects.mask).tolist():
        free[y0:y1, x0:x1] = False
    return torch.nonzero(free)[0].tolist()


def test_a_point_in_an_objects_listed_box_picks_it_the_nearest_in_front_on_overlap(scene):
    """Issue 28's picking by pixel: a point inside an object's listed box but off its mask picks it; where boxes
    overlap the nearest object in front wins; a miss names the nearest objects with their distances in the input's
    pixels (2x the working pixels here)."""
    from sdn3d.image_ops import mask_boxes

    obj = scene.objects
    boxes = mask_boxes(obj.mask)
    frame = PixelFrame((160, 64), (80, 32))
    covered = obj.mask.any(0)
    hits = []
    for row in range(len(obj)):
        x0, y0, x1, y1 = boxes[row].tolist()
        holes = [(x, y) for y in range(y0, y1) for x in range(x0, x1) if not bool(covered[y, x])]
        if holes and bool(obj.has_geometry[row]):
            x, y = holes[0]
            holders = [r for r in range(len(obj)) if boxes[r, 0] <= x < boxes[r, 2] and boxes[r, 1] <= y < boxes[r, 3]]
            front = min(holders, key=lambda r: float(obj.location[r, 2]) if bool(obj.has_geometry[r]) else math.inf)
            [op] = resolve_ops(parse_edit_spec([{"op": "delete", "at": [2 * x + 1, 2 * y + 1]}]), scene,
                               pick_radius=0.001, frame=frame)
            assert op.instance_id == int(obj.instance_id[front])
            hits.append(len(holders))
    assert hits, "no listed box with a pixel off every mask in this scene"
    free = _free_pixel(scene)
    with pytest.raises(EditError) as err:
        resolve_ops(parse_edit_spec([{"op": "delete", "at": [2 * free[1] + 1, 2 * free[0] + 1]}]), scene,
                    pick_radius=0.001, frame=frame)
    nearest = re.findall(r"(\d+) \((\d+) px, centre \[([\d.-]+), ([\d.-]+)\]\)", str(err.value))
    assert 1 <= len(nearest) <= 3 and {int(n[0]) for n in nearest} <= set(obj.instance_id.tolist())
    for _, far, u, v in nearest:  # distances in the input's pixels, from the point as written
        assert abs(float(far) - math.hypot(float(u) - (2 * free[1] + 1), float(v) - (2 * free[0] + 1))) < 1.0


def test_benchmark_route_is_unchanged(scene, tiny_synth):
    spec = load_edit_spec(tiny_synth / "vkitti_edit_benchmark.json", 0)
    assert isinstance(spec, EditSpec) and spec.frame_size == (1242, 375)
    frame = PixelFrame((160, 64), (80, 32))
    assert resolve_ops(spec, scene, frame=frame) == resolve_ops(spec, scene)


def test_cli_spec_in_input_pixels(tiny_synth, ckpts, scene, tmp_path):
    """The dataset frame is stored at 160x64 and worked on at 80x32: the spec says input pixels."""
    row = int(torch.nonzero(scene.objects.has_geometry)[0])
    x, y = _inside_pixel(scene, row)
    (tmp_path / "ops.yaml").write_text(f"- {{op: delete, at: [{2 * x + 0.5}, {2 * y + 0.5}]}}\n")
    out = tmp_path / "out"
    assert main(["data=synth", f"data.root={tiny_synth}", "data.image_size=[80,32]", f"input.frame={FRAME}",
                 f"edits={tmp_path / 'ops.yaml'}", *(f"checkpoints.{k}={v}" for k, v in ckpts.items()),
                 "geometric.crop_size=32", "geometric.min_pixels=1", "proposals=gt", f"output_dir={out}"]) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["ops"] == [{"op": "Delete", "instance_id": int(scene.objects.instance_id[row])}]
    assert summary["input_transform"]["input_size"] == [160, 64] and summary["input_transform"]["mode"] == "resize"


# -- honest about what the weights can do ---------------------------------------------------------------


def test_quality_warning_rules():
    from sdn3d.runs import quality_warnings

    assert quality_warnings({"val/pq": 0.8, "val/miou": 0.1}, 0.2) == []  # PQ known and good: mIoU not asked
    [low] = quality_warnings({"val/pq": 0.9, "val/pq_car": 0.1, "val/pq_van": 0.2}, 0.2, "s.json")
    assert "recorded vehicle PQ is 0.150 (< 0.3, s.json)" in low  # the input unknown: no claim about real photos
    assert "Virtual KITTI or Cityscapes" not in low  # (tests/test_run_warnings.py: when it is said)
    [low] = quality_warnings({"val/miou": 0.12}, None)
    assert "recorded val/miou is 0.120 (< 0.3" in low
    assert quality_warnings(None, 0.5) == [] and quality_warnings({"val/pq": float("nan")}, 0.1) == []
    [cover] = quality_warnings({}, 0.73)
    assert "proposals cover 73 % of the frame (> 50 %)" in cover
    assert len(quality_warnings({"val/pq": 0.01}, 0.9)) == 2
    # the proposals' own recorded recall and precision (what editing needs) decide where a run has them, not PQ
    assert quality_warnings({"val/proposal_recall": 0.7, "val/proposal_precision": 0.6, "val/pq_car": 0.1}, 0.2) == []
    [low] = quality_warnings({"val/proposal_recall": 0.3, "val/proposal_precision": 0.9, "val/pq": 0.9}, None, "s.json")
    assert "recorded proposal recall is 0.300 and precision 0.900 (each must reach 0.5, s.json)" in low
    [low] = quality_warnings({"val/proposal_recall": 0.9, "val/proposal_precision": 0.2}, None)
    assert "precision 0.200" in low
    # one of the two alone is not a proposal record: PQ decides
    assert quality_warnings({"val/proposal_recall": 0.1, "val/pq": 0.8}, None) == []


def _semantic_run(tmp_path, ckpts, metrics):
    """A sdn3d-train-like run directory for the semantic branch: <run>/checkpoints/best.ckpt + summary.json."""
    run = tmp_path / "semantic_run"
    (run / "checkpoints").mkdir(parents=True, exist_ok=True)
    ckpt = run / "checkpoints" / "best.ckpt"
    ckpt.write_bytes(ckpts["semantic"].read_bytes())
    (run / "summary.json").write_text(json.dumps({"branch": "semantic", "status": "ok", "metrics": metrics}))
    return ckpt


def test_low_quality_semantic_branch_is_said(ckpts, tiny_synth, tmp_path, capsys):
    rgb = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    Image.fromarray(np.ascontiguousarray(rgb)).resize((414, 125)).save(tmp_path / "vk.png")
    (tmp_path / "ops.yaml").write_text(SKY)
    ckpt = _semantic_run(tmp_path, ckpts, {"val/pq": 0.04, "val/pq_car": 0.05, "val/miou": 0.2})
    out = tmp_path / "out"
    assert main(_args(ckpts, tmp_path / "vk.png", out, f"checkpoints.semantic={ckpt}")) == 0
    err = capsys.readouterr().err
    assert "sdn3d-edit: warning: the semantic branch's recorded vehicle PQ is 0.050 (< 0.3" in err
    warnings = json.loads((out / "edit.json").read_text())["warnings"]
    assert any("vehicle PQ is 0.050" in w for w in warnings)
    listed = tmp_path / "listed"
    assert main(_args(ckpts, tmp_path / "vk.png", listed, f"checkpoints.semantic={ckpt}", "list=true")) == 0
    assert any("vehicle PQ" in w for w in json.loads((listed / "edit.json").read_text())["warnings"])
    _semantic_run(tmp_path, ckpts, {"val/pq": 0.9, "val/pq_car": 0.85})
    capsys.readouterr()
    assert main(_args(ckpts, tmp_path / "vk.png", out, f"checkpoints.semantic={ckpt}")) == 0
    assert "recorded" not in capsys.readouterr().err
    assert not any("recorded" in w for w in json.loads((out / "edit.json").read_text())["warnings"])


def test_low_quality_warning_names_the_real_cause_by_the_input(ckpts, tiny_synth, tmp_path, capsys):
    """sdn3d-edit tells the warning what the input is: a photo from elsewhere needs other weights; a frame of the
    data the run trained on means the branch itself is weak."""
    rgb = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    Image.fromarray(np.ascontiguousarray(rgb)).resize((414, 125)).save(tmp_path / "vk.png")
    (tmp_path / "ops.yaml").write_text(SKY)
    ckpt = _semantic_run(tmp_path, ckpts, {"val/pq": 0.04, "val/pq_car": 0.05})
    (ckpt.parent.parent / "config.yaml").write_text(f"data:\n  kind: vkitti1\n  root: {tiny_synth}\n")
    assert main(_args(ckpts, tmp_path / "vk.png", tmp_path / "photo", f"checkpoints.semantic={ckpt}")) == 0
    err = capsys.readouterr().err
    assert "this input is not from the data the run trained on" in err and "real photos need" in err
    assert main(["data=synth", f"data.root={tiny_synth}", "data.image_size=[80,32]", f"input.frame={FRAME}",
                 f"edits={tmp_path / 'ops.yaml'}", *(f"checkpoints.{k}={v}" for k, v in ckpts.items()),
                 f"checkpoints.semantic={ckpt}", "geometric.crop_size=32", "proposals=semantic",
                 "appearance=generator", f"output_dir={tmp_path / 'frame'}"]) == 0
    err = capsys.readouterr().err
    assert "this input is from the data the run trained on" in err and "real photos need" not in err


def test_dataset_ground_truth_proposals_give_no_warning(tiny_synth, ckpts, tmp_path, capsys):
    ckpt = _semantic_run(tmp_path, ckpts, {"val/pq": 0.01})
    (tmp_path / "ops.yaml").write_text(SKY)
    out = tmp_path / "out"
    assert main(["data=synth", f"data.root={tiny_synth}", "data.image_size=[80,32]", f"input.frame={FRAME}",
                 f"edits={tmp_path / 'ops.yaml'}", *(f"checkpoints.{k}={v}" for k, v in ckpts.items()),
                 f"checkpoints.semantic={ckpt}", "geometric.crop_size=32", "proposals=gt", "appearance=generator",
                 f"output_dir={out}"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert json.loads((out / "edit.json").read_text())["warnings"] == []


def _cfg(tmp_path, **input_node):
    from omegaconf import OmegaConf

    node = {"image": str(tmp_path / "street.png"), "intrinsics": None, "camera": None, "frame": None, **input_node}
    return OmegaConf.create({"input": node, "box_objects": {"prior": False, "fit": {"camera_height": 1.65}}})


def test_the_given_camera_sets_the_road_plane_of_the_box_fit(tmp_path):
    """issue 40: a camera.json's height and pitch (and input.intrinsics' optional camera_height and pitch) reach
    the box fit: the height as FitSettings.camera_height, the pitch folded into cy (the level virtual camera)."""
    from sdn3d.cli.edit import _given_camera, box_fit_for_input, camera_record
    from sdn3d.editing.settings import box_settings

    camera = _camera_json(tmp_path / "c.json", CAMERA)
    cfg = _cfg(tmp_path, camera=str(camera))
    intr = _given_camera(cfg, 256, 128)
    assert intr.cy == pytest.approx(60.0 - 310.0 * math.tan(0.04)) and intr.fx == 300.0 and intr.cx == 130.0
    assert box_fit_for_input(cfg, box_settings(cfg, {})[0]).camera_height == pytest.approx(1.2)
    # input.intrinsics with a pose: the same; without: as before (1.65 m, cy as given).
    cfg = _cfg(tmp_path, intrinsics={"fx": 300, "fy": 310, "cx": 130, "cy": 60, "camera_height": 1.3, "pitch": -0.02})
    assert _given_camera(cfg, 256, 128).cy == pytest.approx(60.0 + 310.0 * math.tan(0.02))
    assert box_fit_for_input(cfg, box_settings(cfg, {})[0]).camera_height == pytest.approx(1.3)
    record = camera_record(cfg)
    assert record["camera_height"] == 1.3 and record["pitch"] == -0.02 and record["pose_from"] == "input.intrinsics"
    cfg = _cfg(tmp_path, intrinsics={"fx": 300, "fy": 310, "cx": 130, "cy": 60, "pitch": 0.03})
    # no height given: box_objects.fit.camera_height
    assert box_fit_for_input(cfg, box_settings(cfg, {})[0]).camera_height == 1.65
    assert camera_record(cfg)["camera_height_from"] == "box_objects.fit.camera_height"
    cfg = _cfg(tmp_path, intrinsics={"fx": 300, "fy": 310, "cx": 130, "cy": 60})
    assert _given_camera(cfg, 256, 128) == Intrinsics(300, 310, 130, 60, 256, 128)
    assert box_fit_for_input(cfg, box_settings(cfg, {})[0]).camera_height == 1.65
    assert camera_record(cfg) == {"camera_height": 1.65, "camera_height_from": "box_objects.fit.camera_height",
                                  "pitch": 0.0, "roll": 0.0, "pose_from": None}
    # A dataset frame: input.camera is not its camera.
    cfg = _cfg(tmp_path, image=None, camera=str(camera), frame="0001/clone/00000")
    assert box_fit_for_input(cfg, box_settings(cfg, {})[0]).camera_height == 1.65


@pytest.mark.parametrize("given, words", [
    ({"camera_height": 0}, "camera_height must be positive"),
    ({"camera_height": "high"}, "camera_height must be a finite number"),
    ({"pitch": 1.0}, "pitch must be within"),
])
def test_a_bad_camera_pose_is_refused_naming_the_setting(tmp_path, given, words):
    from sdn3d.cli.edit import InputError, _given_camera

    cfg = _cfg(tmp_path, intrinsics={"fx": 300, "fy": 310, "cx": 130, "cy": 60, **given})
    with pytest.raises(InputError, match=f"input.intrinsics: .*{words}"):
        _given_camera(cfg, 256, 128)
