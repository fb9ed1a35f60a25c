"""``sdn3d-edit`` end to end on the tiny synthetic dataset with random-weight checkpoints."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
import torch
import trimesh
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d.cli.edit import main
from sdn3d.data import vkitti1
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.editing.spec import EditSpecError, parse_edit_spec
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.math3d.rotations import wrap_angle
from sdn3d.scene.io import load_scene
from sdn3d.textural.code_bank import save_code_bank
from sdn3d.textural.codes import CodeBank

FRAME = "0001/clone/00004"
BANK = {12: torch.arange(40.0).view(8, 5), 13: torch.ones(2, 5)}  # training codes per class (Car, Van)
BANK_COLORS = {12: torch.linspace(0, 1, 24).view(8, 3), 13: torch.ones(2, 3)}  # their objects' mean colours


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def _args(tiny_synth, ckpts, out, edits, *extra):
    return ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"edits={edits}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32",
            "geometric.min_pixels=1", "proposals=gt", f"output_dir={out}", "appearance=generator", *extra]
    # gt: random weights find no car; appearance=generator: these tests are of the generator path (photo: test_photo)


def _write(path, text):
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def done(tiny_synth, ckpts, tmp_path_factory):
    """One successful run: rotate, move (picked by pixel), delete and recolour on frame 00004."""
    tmp = tmp_path_factory.mktemp("edit")
    source = scene_from_frame(vkitti1.read_frames(tiny_synth)[4], (160, 64))
    ids = source.objects.instance_id.tolist()
    ys, xs = source.objects.mask[1].nonzero(as_tuple=True)
    at = [int(xs[len(xs) // 2]), int(ys[len(ys) // 2])]
    edits = _write(tmp / "ops.yaml", f"""
- {{op: rotate, id: {ids[0]}, ry_rad: 0.5}}
- {{op: move, at: {at}, to: [40, 55]}}
- {{op: delete, id: {ids[2]}}}
- {{op: recolor, class: Road, code: [0.1, 0.2, 0.3, 0.4, 0.5]}}
- {{op: recolor, id: {ids[3]}, sample: true, seed: 3}}
- {{op: duplicate, id: {ids[0]}, to: [150, 34]}}  # clear of the (random) cars in 3D
""")
    save_code_bank(CodeBank(BANK, BANK_COLORS), tmp / "bank.json")
    out = tmp / "out"
    code = main(_args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}", f"code_bank={tmp / 'bank.json'}",
                      "diagnostics=true"))
    return code, out, ids


def test_edit_writes_every_output(done):
    code, out, ids = done
    assert code == 0
    for name in ("source.png", "reconstruction.png", "generated.png", "edited.png", "overview.png", "scene.json",
                 "scene.npz", "edited_scene.json", "edited_scene.npz", "scene.glb", "edited_scene.glb", "edit.json",
                 "maps/edit_region.png"):
        assert (out / name).is_file(), name
    for which in ("source", "edited"):
        for kind in ("label", "instance", "normal", "pose", "depth"):
            assert np.asarray(Image.open(out / "maps" / f"{which}_{kind}.png")).shape == (64, 160, 3)
    assert np.asarray(Image.open(out / "edited.png")).shape == (64, 160, 3)
    assert not any(p.name.startswith(".") for p in out.parent.iterdir())  # no staging leftovers


def test_edit_applies_the_resolved_ops(done):
    _, out, ids = done
    summary = json.loads((out / "edit.json").read_text())
    ops = summary["ops"]
    assert [o["op"] for o in ops] == ["Rotate", "Move", "Delete", "SetBackgroundCode", "SetCode", "Duplicate"]
    assert summary["proposals"] == {"masks": "gt", "semantics": "gt", "oracle": True,
                                    "label": "oracle: ground-truth masks and semantics"}
    assert ops[1]["instance_id"] == ids[1]  # `at` picked the object under the pixel
    scene, edited = load_scene(out / "scene.json"), load_scene(out / "edited_scene.json")
    assert scene.objects.instance_id.tolist() == ids
    assert ids[2] not in edited.objects.instance_id.tolist()
    r0, e0 = scene.objects.index_of(ids[0]), edited.objects.index_of(ids[0])
    assert float(wrap_angle(edited.objects.ry[e0] - scene.objects.ry[r0] - 0.5)) == pytest.approx(0, abs=1e-9)
    moved = edited.objects.index_of(ids[1])
    intr = edited.intrinsics
    c = edited.objects.center[moved]
    uv = (float(c[0] / c[2] * intr.fx + intr.cx), float(c[1] / c[2] * intr.fy + intr.cy))
    assert uv == pytest.approx((40, 55), abs=1e-6)  # the centre projects to the target pixel
    road = [c.id for c in scene.class_list if c.name == "Road"][0]
    assert edited.background_codes[road].tolist() == pytest.approx([0.1, 0.2, 0.3, 0.4, 0.5])
    sampled = CodeBank(BANK).sample(ids[3] // 1000, 1, torch.Generator().manual_seed(3))
    assert edited.objects.code[edited.objects.index_of(ids[3])].tolist() == sampled[0].tolist()
    copy = edited.objects.index_of(next(i for i in edited.objects.instance_id.tolist() if i not in ids))
    assert len(edited.objects) == len(ids) and not bool(edited.objects.observed[copy])  # one deleted, one added
    torch.testing.assert_close(edited.objects.code[copy], edited.objects.code[e0])
    glb = trimesh.load(out / "edited_scene.glb")
    assert "ground" in glb.graph.nodes and f"instance_{ids[2]}" not in glb.graph.nodes


def _kept(out, input_size):
    """``(H_in, W_in)`` bool: input pixels whose nearest working pixel is more than one pixel from the edit
    region (maps/edit_region.png), i.e. pixels compose=edited must leave exactly as they were."""
    from sdn3d.editing.frame import PixelFrame

    summary = json.loads((out / "edit.json").read_text())
    t = summary["input_transform"]
    frame = PixelFrame(tuple(t["input_size"]), tuple(t["working_size"]), tuple(t["scaled_size"]),
                       tuple(t["crop_offset"]))
    region = torch.from_numpy(np.asarray(Image.open(out / "maps" / "edit_region.png")) > 0)
    near = torch.nn.functional.max_pool2d(region[None, None].float(), 3, 1, 1)[0, 0].bool()
    w, h = frame.working_size
    v, u = np.meshgrid(np.arange(input_size[1]), np.arange(input_size[0]), indexing="ij")
    uw, vw = frame.to_working((u, v))
    ju, iv = np.rint(uw).astype(int), np.rint(vw).astype(int)
    inside = (ju >= 0) & (ju < w) & (iv >= 0) & (iv < h)
    touched = np.zeros(inside.shape, bool)
    touched[inside] = near.numpy()[iv[inside], ju[inside]]
    return ~touched


def test_edited_png_keeps_every_untouched_pixel_of_the_frame(done, tiny_synth, ckpts, tmp_path):
    _, out, ids = done
    summary = json.loads((out / "edit.json").read_text())
    assert summary["compose"]["mode"] == "edited" and summary["compose"]["output_size"] == [160, 64]
    assert set(ids[:4]) <= set(summary["compose"]["edited_objects"]) and summary["timings_ms"]["compose_ms"] > 0
    # The road was recoloured: it spans the frame's lower part (the rest changes where the edited cars are and went).
    assert summary["compose"]["region_fraction"] > 0.5
    edits = _write(tmp_path / "ops.yaml", f"- {{op: delete, id: {ids[2]}}}")
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}")) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["compose"]["edited_objects"] == [ids[2]] and 0 < summary["compose"]["region_fraction"] < 0.5
    source = vkitti1.load_rgb([r for r in vkitti1.read_frames(tiny_synth) if r.key.endswith(FRAME)][0])
    edited, generated = (np.asarray(Image.open(out / name)) for name in ("edited.png", "generated.png"))
    kept = _kept(out, (160, 64))
    assert kept.any() and (edited[kept] == source[kept]).all()  # bit for bit
    # Without diagnostics=true only what an edit needs is written: no reconstruction pass, no glTF export.
    written = {str(p.relative_to(out)) for p in out.rglob("*") if p.is_file()}
    assert written == {"edited.png", "generated.png", "maps/edit_region.png", "scene.json", "scene.npz",
                       "edited_scene.json", "edited_scene.npz", "edit.json"}
    deleted = scene_from_frame(vkitti1.read_frames(tiny_synth)[4], (160, 64)).objects.mask[2].numpy()
    assert (edited[deleted] != source[deleted]).any() and (generated[kept] != source[kept]).any()


@pytest.mark.parametrize("ops, message", [
    ("- {op: rotate, id: 12999, ry_deg: 30}", r"op 0 \(rotate id=12999\): no object with id 12999"),
    ("- {op: zoom, id: 12002, zoom: .nan}", r"op 0 \(zoom\): field 'zoom' must be finite"),
    ("- {op: rotate, id: 12002, ry_deg: 5}\n- {op: zoom, id: 12002, zoom: -2}", r"op 1 \(zoom\).*must be > 0"),
    ("- {op: move, id: 12002, to: [400, 20]}", r"op 0 \(move id=12002\): 'to' point \[400.0, 20.0\] lies outside"),
    ("- {op: delete, at: [2, 2]}", r"op 0 \(delete at=\[2.0, 2.0\]\): no object at"),
    ("- {op: recolor, id: 12002, sample: true}", r"op 0 \(recolor id=12002\): 'sample: true' needs a code bank"),
    ("- {op: spin, id: 12002}", r"field 'op' must be one of"),
    ("- {op: zoom, id: 12002, zoom: 1.0e9}", r"op 0 \(zoom id=12002\): Zoom: object 12002 would end .* closer than"),
    ("- {op: zoom, id: 12002, zoom: 1e-9}", r"op 0 \(zoom id=12002\): .* farther than 1000 m \(the far plane"),
    ("- {op: zoom, id: 12002, zoom: huge}", r"op 0 \(zoom\): field 'zoom' must be a number, got 'huge'"),
])
def test_bad_edits_exit_2_and_write_nothing(tiny_synth, ckpts, tmp_path, capsys, ops, message):
    edits = _write(tmp_path / "ops.yaml", ops)
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}", "pick_radius=3")) == 2
    err = capsys.readouterr().err
    assert err.startswith("sdn3d-edit: error:") and re.search(message, err), err
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["ops.yaml"]


def test_output_dir_safety(tiny_synth, ckpts, tmp_path, capsys):
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    unrelated = tmp_path / "mine"
    unrelated.mkdir()
    (unrelated / "notes.txt").write_text("keep me")
    assert main(_args(tiny_synth, ckpts, unrelated, edits, f"input.frame={FRAME}")) == 2
    assert "holds no edit.json" in capsys.readouterr().err and (unrelated / "notes.txt").read_text() == "keep me"
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}")) == 0
    assert main(_args(tiny_synth, ckpts, out, edits, "input.frame=4")) == 0  # an earlier result: replaced
    (out / "stale.txt").write_text("old")  # a file the earlier run did not write (issue 32): never deleted
    assert main(_args(tiny_synth, ckpts, out, edits, "input.frame=4")) == 2
    assert "'stale.txt'" in capsys.readouterr().err and (out / "stale.txt").read_text() == "old"


# The Virtual KITTI camera resized to 320x128: what a 320x128 image silently got before the camera had to be
# given (piece 1 of "Editing a picture as a user would"); 320x128 is not Virtual KITTI's aspect ratio.
VKITTI_AT_320x128 = ("input.intrinsics={fx:" + repr(725 * 320 / 1242) + ",fy:" + repr(725 * 128 / 375)
                     + ",cx:" + repr(621 * 320 / 1242 - 0.5) + ",cy:" + repr(187.5 * 128 / 375 - 0.5) + "}")


def test_image_file_input_with_given_camera(tiny_synth, ckpts, tmp_path):
    rgb = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    Image.fromarray(np.ascontiguousarray(rgb)).resize((320, 128)).save(tmp_path / "street.png")
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    out = tmp_path / "out"
    args = [f"input.image={tmp_path / 'street.png'}", "image_size=[160,64]", f"edits={edits}", VKITTI_AT_320x128,
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", "appearance=generator",
            f"output_dir={out}"]
    assert main(args) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["intrinsics"]["width"] == 160 and math.isclose(summary["intrinsics"]["fx"], 725 * 160 / 1242)
    assert np.asarray(Image.open(out / "generated.png")).shape == (64, 160, 3)  # the working size
    assert main(args[:-1] + [f"output_dir={tmp_path / 'o2'}", "checkpoints.textural=null"]) == 2


def _oracle_scene(record, frame, intrinsics):
    """The frame's ground-truth scene seen through ``frame`` (scaled, then cropped) with ``intrinsics``."""
    scene = scene_from_frame(record, frame.scaled_size or frame.working_size, 5)
    (left, top), (w, h) = frame.offset, frame.working_size
    objects = scene.objects.replace(mask=scene.objects.mask[:, top:top + h, left:left + w])
    return scene.replace(intrinsics=intrinsics, semantic=scene.semantic[top:top + h, left:left + w], objects=objects)


@pytest.mark.parametrize("size", [(320, 128), (240, 120)])
def test_edited_png_has_the_input_images_resolution(tiny_synth, ckpts, tmp_path, capsys, monkeypatch, size):
    """320x128: a plain 2x resize to 160x64; 240x120 (another aspect ratio): scaled to 160x80 and cropped.
    The random-weight semantic branch finds no object, so the frame's ground-truth scene stands in for
    de-rendering (the compose step is under test)."""
    import sdn3d.derender
    from sdn3d.editing.inputs import fit_transform

    record = vkitti1.read_frames(tiny_synth)[4]
    Image.fromarray(np.ascontiguousarray(vkitti1.load_rgb(record))).resize(size).save(tmp_path / "street.png")
    picture = np.asarray(Image.open(tmp_path / "street.png").convert("RGB"))
    frame = fit_transform((160, 64), size)
    monkeypatch.setattr(sdn3d.derender, "derender", lambda image, intrinsics, *a, **k:
                        _oracle_scene(record, frame, intrinsics))
    masks = _oracle_scene(record, frame, VKITTI_INTRINSICS.resized(160, 64)).objects
    victim = int(masks.instance_id[int(masks.mask.flatten(1).sum(1).argmax())])  # the largest object in view
    edits = _write(tmp_path / "ops.yaml", f"- {{op: delete, id: {victim}}}")
    camera = f"input.intrinsics={{fx:{size[0]},fy:{size[0]},cx:{size[0] / 2 - 0.5},cy:{size[1] / 2 - 0.5}}}"
    base = [f"input.image={tmp_path / 'street.png'}", "image_size=[160,64]", f"edits={edits}", camera,
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", "geometric.min_pixels=1",
            "appearance=generator"]
    out = tmp_path / "out"
    assert main([*base, f"output_dir={out}"]) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["input_transform"]["mode"] == ("resize" if size == (320, 128) else "scale_crop")
    edited = np.asarray(Image.open(out / "edited.png"))
    assert edited.shape == (size[1], size[0], 3) and summary["compose"]["output_size"] == list(size)
    kept = _kept(out, size)
    assert (edited[kept] == picture[kept]).all() and (edited[~kept] != picture[~kept]).any()
    full = tmp_path / "full"
    assert main([*base, f"output_dir={full}", "compose=full"]) == 0
    edited_full = np.asarray(Image.open(full / "edited.png"))
    assert edited_full.shape == (64, 160, 3) and (edited_full == np.asarray(Image.open(full / "generated.png"))).all()
    assert json.loads((full / "edit.json").read_text())["compose"]["mode"] == "full"
    assert not (full / "maps" / "edit_region.png").exists()
    assert main([*base, f"output_dir={tmp_path / 'bad'}", "compose=partial"]) == 2
    assert "compose must be one of ('edited', 'full'), got 'partial'" in capsys.readouterr().err


@pytest.mark.parametrize("bomb", ["declared", "blank"])
def test_decompression_bomb_image_is_refused_naming_the_file(ckpts, tmp_path, capsys, bomb):
    """Issue 20: a PNG declaring 400 MP crashed with PIL's DecompressionBombError; one of 105 MP was decoded."""
    from faults.images import blank_png, declared_size_png

    image = (declared_size_png(tmp_path / "bomb.png", 20000, 20000) if bomb == "declared"
             else blank_png(tmp_path / "bomb.png", 10500, 10000))
    assert image.stat().st_size < 20_000
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    out = tmp_path / "out"
    args = [f"input.image={image}", "image_size=[160,64]", f"edits={edits}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", f"output_dir={out}"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sdn3d-edit: error: input.image {str(image)!r}: image too large") and err.count("\n") == 1
    assert "100 MP limit" in err and not out.exists()


def test_an_image_far_from_the_working_aspect_ratio_is_refused_before_decoding(ckpts, tmp_path, capsys):
    """Issue 42 (5): a 10x20000 PNG (200 kP, far under the 100 MP limit) was scaled to cover the working size before
    the crop: 18.5 GB at 1242x375. Now it is refused from its header, naming the file and both sizes."""
    from faults.images import declared_size_png

    image = declared_size_png(tmp_path / "tall.png", 10, 20000)
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    out = tmp_path / "out"
    args = [f"input.image={image}", "image_size=[1242,375]", f"edits={edits}",
            "input.intrinsics={fx:725,fy:725,cx:5,cy:10000}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", f"output_dir={out}"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"sdn3d-edit: error: input.image {str(image)!r}: a 10x20000 image (aspect ratio 0.0005) is "
                          "too far from the working size 1242x375 (3.31): scaled to cover it, it would be "
                          "1242x2484000 pixels, more than 16 times the working size; crop it closer to 1242:375"), err
    assert err.count("\n") == 1 and not out.exists()


def test_a_full_disk_is_one_line_exit_1_and_the_earlier_output_stays(tiny_synth, ckpts, tmp_path, capsys,
                                                                      monkeypatch):
    """Issue 42 (8): a full disk raised OSError [Errno 28] with a traceback; now one line saying the disk is full,
    naming the output directory, exit 1 (as training's), the earlier output untouched and nothing half-written."""
    import errno

    import sdn3d.io

    out = tmp_path / "out"
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    args = _args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}", "overwrite=true")
    assert main(args) == 0
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    capsys.readouterr()

    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(sdn3d.io.os, "fsync", full)
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"sdn3d-edit: error: the disk is full: could not write output_dir {str(out)!r} (") and \
        err.count("\n") == 1 and "Traceback" not in err, err
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".out.")) == []


def test_benchmark_entry_picks_its_source_frame(tiny_synth, ckpts, tmp_path):
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out, tiny_synth / "vkitti_edit_benchmark.json", "entry=0")) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["refined"] is False  # Virtual KITTI data: the Cityscapes fit is off by default
    assert summary["input"] == "vkitti1/0001/clone/00007" and {o["op"] for o in summary["ops"]} == {"Modify"}
    assert main(_args(tiny_synth, ckpts, tmp_path / "o2", tiny_synth / "vkitti_edit_benchmark.json",
                      "entry=3")) == 2


def test_refinement_runs_when_enabled(tiny_synth, ckpts, tmp_path):
    """refine.enabled=true (auto: Cityscapes only) runs the paper's test-time fit inside the de-rendering."""
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out, tiny_synth / "vkitti_edit_benchmark.json", "entry=0",
                      "refine.enabled=true", "refine.iterations=2")) == 0
    assert json.loads((out / "edit.json").read_text())["refined"] is True
    assert main(_args(tiny_synth, ckpts, tmp_path / "bad", tiny_synth / "vkitti_edit_benchmark.json", "entry=0",
                      "refine.enabled=sometimes")) == 2


def test_spec_parser_checks_fields():
    spec = parse_edit_spec({"frame_size": [1242, 375], "ops": [{"op": "duplicate", "id": 12001, "to": [1, 2]}]})
    assert spec.frame_size == (1242, 375) and spec.ops[0].to == (1.0, 2.0) and spec.ops[0].new_id is None
    for bad, message in [([{"op": "move", "id": 12001}], "'to'"),
                         ([{"op": "move", "id": 12001, "at": [1, 2], "to": [1, 2]}], "exactly one"),
                         ([{"op": "rotate", "id": 12001, "ry_deg": 1, "zom": 2}], "unknown field"),
                         ([{"op": "recolor", "id": 12001, "code": [1], "sample": True}], "exactly one"),
                         ([{"op": "rotate", "id": True, "ry_deg": 1}], "'id'"), ([], "non-empty")]:
        with pytest.raises(EditSpecError, match=message):
            parse_edit_spec(bad)


# -- run=: the branches' checkpoints from training summaries ----------------------------------------------


def _train_run(run_dir, branch, ckpt, status="ok", finished="2026-01-01T10:00:00+00:00", best=True):
    """A ``sdn3d-train`` run directory: ``checkpoints/{best,last}.ckpt`` (copies of ``ckpt``) and summary.json."""
    import shutil

    (run_dir / "checkpoints").mkdir(parents=True)
    last = shutil.copy(ckpt, run_dir / "checkpoints" / "last.ckpt")
    best_path = shutil.copy(ckpt, run_dir / "checkpoints" / "epoch=0-step=1.ckpt") if best else None
    summary = {"branch": branch, "run_dir": str(run_dir), "best_ckpt": best_path and str(best_path),
               "last_ckpt": str(last), "status": status, "finished": finished}
    (run_dir / "summary.json").write_text(json.dumps(summary))
    return run_dir


def _demo_layout(root, ckpts, branches=("semantic", "geometric", "textural")):
    for branch in branches:
        _train_run(root / "runs" / branch, branch, ckpts[branch])
    (root / "summary.json").write_text(json.dumps({"stages": {}, "wall_s": 1.0}))  # the demo's own summary
    (root / "runs" / "summary.jsonl").write_text("")
    return root


def test_run_dir_finds_the_demo_checkpoints(tiny_synth, ckpts, tmp_path, capsys):
    run = _demo_layout(tmp_path / "demo", ckpts)
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    out = tmp_path / "out"
    args = ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"edits={edits}", f"run={run}",
            "geometric.crop_size=32", f"output_dir={out}", f"input.frame={FRAME}"]
    assert main(args) == 0
    err = capsys.readouterr().err
    used = json.loads((out / "edit.json").read_text())["checkpoints"]
    for branch in ("semantic", "geometric", "textural"):
        expected = (run / "runs" / branch / "checkpoints" / "epoch=0-step=1.ckpt").resolve()
        assert used[branch]["path"] == str(expected) and used[branch]["which"] == "best"
        assert used[branch]["from"] == str(run / "runs" / branch / "summary.json")
        assert f"sdn3d-edit: {branch} checkpoint: {expected} (best checkpoint" in err
    # an explicit checkpoints.<branch> wins over the run's
    assert main([*args[:-2], f"output_dir={tmp_path / 'o2'}", f"input.frame={FRAME}",
                 f"checkpoints.textural={ckpts['textural']}"]) == 0
    used = json.loads((tmp_path / "o2" / "edit.json").read_text())["checkpoints"]
    assert used["textural"] == {"path": str(ckpts["textural"]), "from": "checkpoints.textural"}
    assert used["geometric"]["which"] == "best"


def test_run_dir_layouts_and_choice(ckpts, tmp_path):
    from sdn3d.runs import find_run_checkpoints

    single = _train_run(tmp_path / "one", "geometric", ckpts["geometric"], best=False)  # a single run directory
    chosen, missing = find_run_checkpoints(single)
    assert chosen["geometric"]["which"] == "last" and set(missing) == {"semantic", "textural"}
    assert chosen["geometric"]["path"] == str((single / "checkpoints" / "last.ckpt").resolve())

    root = tmp_path / "train"  # a training root: <branch>/<time>/summary.json
    _train_run(root / "geometric" / "a", "geometric", ckpts["geometric"], finished="2026-01-01T10:00:00+00:00")
    newest = _train_run(root / "geometric" / "b", "geometric", ckpts["geometric"], finished="2026-01-02T10:00:00+00:00")
    _train_run(root / "textural" / "a", "textural", ckpts["textural"], finished="2026-01-01T10:00:00+00:00", best=False)
    _train_run(root / "textural" / "b", "textural", ckpts["textural"], status="failed",
               finished="2026-01-03T10:00:00+00:00")  # newer but failed: not used
    _train_run(root / "semantic" / "a", "semantic", ckpts["semantic"], status="interrupted")
    chosen, missing = find_run_checkpoints(root)
    assert chosen["geometric"]["summary"] == str(newest / "summary.json")
    assert chosen["textural"]["which"] == "last" and "textural/a/" in chosen["textural"]["path"]
    assert "semantic" not in chosen and "status interrupted" in missing["semantic"]

    moved = tmp_path / "moved"  # a run directory moved after training: checkpoints/ beside the summary
    (tmp_path / "one").rename(moved)
    assert find_run_checkpoints(moved)[0]["geometric"]["path"] == str((moved / "checkpoints" / "last.ckpt").resolve())


@pytest.mark.parametrize("case, message", [
    ("missing", r"run '.*nowhere' does not exist"),
    ("empty", r"run '.*empty' holds no training summary \(1 summary.json file\(s\), none from sdn3d-train\)"),
    ("no_textural", r"run '.*demo' lacks the textural branch the edit needs \(textural: no run\); found "
                    r"semantic: epoch=0-step=1.ckpt \(best\); geometric: .* give checkpoints.textural="),
    ("failed_geometric", r"lacks the geometric branch .*geometric: 1 run\(s\) \(status failed\) but none ok"),
])
def test_bad_run_dir_exits_2(tiny_synth, ckpts, tmp_path, capsys, case, message):
    run = {"missing": tmp_path / "nowhere", "empty": tmp_path / "empty"}.get(case, tmp_path / "demo")
    if case == "empty":
        run.mkdir()
        (run / "summary.json").write_text(json.dumps({"stages": {}}))
    elif case == "no_textural":
        _demo_layout(run, ckpts, ("semantic", "geometric"))
    elif case == "failed_geometric":
        _demo_layout(run, ckpts, ("semantic", "textural"))
        _train_run(run / "runs" / "geometric", "geometric", ckpts["geometric"], status="failed")
    edits = _write(tmp_path / "ops.yaml", "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}")
    out = tmp_path / "out"
    args = ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"edits={edits}", f"run={run}",
            f"output_dir={out}", f"input.frame={FRAME}"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("sdn3d-edit: error: run ") and err.count("\n") == 1 and re.search(message, err), err
    assert not out.exists()


def test_default_proposals_without_a_semantic_branch_say_what_to_give(tiny_synth, ckpts, tmp_path, capsys):
    edits = _write(tmp_path / "ops.yaml", "- {op: delete, id: 12002}")
    out = tmp_path / "out"
    args = [a for a in _args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}")
            if not a.startswith(("proposals=", "checkpoints.semantic="))]
    assert main(args) == 2 and not out.exists()
    err = capsys.readouterr().err
    assert "checkpoints.semantic=<file>" in err and "run=" in err and "proposals=gt" in err


def test_photo_appearance_is_the_default_and_keeps_every_untouched_pixel(tiny_synth, ckpts, tmp_path, capsys):
    """``appearance`` unset: the photo appearance. The edited car is drawn from the frame's own pixels (no generator
    pass), ``maps/photo_source.png`` says where each pixel came from, ``edit.json`` records it, and every pixel the
    source map calls input is the frame's, bit for bit."""
    source = scene_from_frame(vkitti1.read_frames(tiny_synth)[4], (160, 64))
    ids = source.objects.instance_id[source.objects.has_geometry].tolist()
    edits = _write(tmp_path / "ops.yaml", f"- {{op: rotate, id: {ids[0]}, ry_deg: 30}}\n"
                                          f"- {{op: recolor, id: {ids[1]}, color: blue}}\n")
    out = tmp_path / "out"
    args = [a for a in _args(tiny_synth, ckpts, out, edits, f"input.frame={FRAME}") if a != "appearance=generator"]
    assert main(args) == 0
    summary = json.loads((out / "edit.json").read_text())
    assert summary["appearance"] == "photo" and summary["compose"]["mode"] == "photo"
    assert "photo_ms" in summary["timings_ms"] and "render_ms" not in summary["timings_ms"]  # no generator pass
    photo = summary["photo"]
    assert photo["settings"]["fill"] == "rays" and photo["source_pixels"]["input"] > 0
    assert photo["objects"][str(ids[1])]["recolor"]["color"] == pytest.approx([0.10, 0.25, 0.70])
    assert not (out / "generated.png").exists() and (out / "maps" / "photo_source.png").is_file()
    edited = np.asarray(Image.open(out / "edited.png"))
    frame = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    sources = np.asarray(Image.open(out / "maps" / "photo_source.png"))
    untouched = (sources == (40, 40, 40)).all(-1)
    assert edited.shape == frame.shape and (edited[untouched] == frame[untouched]).all()
    assert not untouched.all() and "appearance photo" in capsys.readouterr().out
    assert main([*args[:-1], f"output_dir={tmp_path / 'bad'}", "appearance=paint"]) == 2
    assert "appearance must be one of ['photo', 'generator']" in capsys.readouterr().err
    assert main([*args[:-1], f"output_dir={tmp_path / 'bad'}", "+photo.fil=telea"]) == 2
    assert "photo: unknown setting(s) ['fil']" in capsys.readouterr().err


def test_the_program_ends_without_the_interpreters_teardown(tmp_path):
    """Run as the program (no argv), sdn3d-edit ends its process once done (issue 40: the teardown costs 0.15 CPU s
    and writes nothing): the exit status and everything printed arrive, through pipes too; atexit hooks do not run.
    Called with arguments (tests, benchmarks) main returns."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    src = str(Path(__file__).resolve().parents[1] / "src")
    code = ("import atexit, sys\nimport sdn3d.cli.edit as e\natexit.register(lambda: print('teardown'))\n"
            "sys.argv = ['sdn3d-edit', 'input.image=' + sys.argv[1], 'list=true', 'output_dir=' + sys.argv[2]]\n"
            "print('before', end='')\nsys.exit(e.main())\n")
    env = {**os.environ, "PYTHONPATH": src + os.pathsep + os.environ.get("PYTHONPATH", ""), "OMP_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, "-c", code, str(tmp_path / "missing.png"), str(tmp_path / "out")],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 2 and done.stdout == "before"  # no 'teardown': the process ended in main
    assert "sdn3d-edit: error: input.image" in done.stderr and "not found" in done.stderr
    assert main(["input.image=" + str(tmp_path / "missing.png"), "list=true", f"output_dir={tmp_path / 'o'}"]) == 2
