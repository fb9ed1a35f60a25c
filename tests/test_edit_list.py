"""``sdn3d-edit list=true`` (or an empty edit spec): the found objects, in the input image's pixels."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d.cli.edit import main
from sdn3d.data import vkitti1
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.image_ops import mask_boxes

FRAME = "0001/clone/00004"
FIELDS = {"id", "class", "box", "centre", "distance_m", "yaw_deg", "template", "xyz_m"}


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def _args(tiny_synth, ckpts, out, *extra):
    """A dataset frame stored at 160x64, worked on at 80x32 (so input pixels = 2 x working pixels)."""
    return ["data=synth", f"data.root={tiny_synth}", "data.image_size=[80,32]", f"input.frame={FRAME}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32",
            "geometric.min_pixels=1", "proposals=gt", f"output_dir={out}", *extra]  # gt: random weights find no car


@pytest.fixture(scope="module")
def listed(tiny_synth, ckpts, tmp_path_factory):
    out = tmp_path_factory.mktemp("list") / "out"
    return main(_args(tiny_synth, ckpts, out, "list=true")), out


def test_list_writes_only_the_listing(listed, capsys):
    code, out = listed
    assert code == 0
    assert sorted(p.name for p in out.iterdir()) == ["edit.json", "objects.json", "objects.png"]
    summary = json.loads((out / "edit.json").read_text())
    assert summary["mode"] == "list" and summary["outputs"] == ["objects.json", "objects.png", "edit.json"]
    assert not any(p.name.startswith(".") for p in out.parent.iterdir())  # no staging leftovers


def test_list_ids_fields_and_input_pixels(listed, tiny_synth):
    _, out = listed
    record = vkitti1.read_frames(tiny_synth)[4]
    truth = scene_from_frame(record, (80, 32))
    listing = json.loads((out / "objects.json").read_text())
    assert listing["input_size"] == [160, 64] and listing["working_size"] == [80, 32]
    assert "input-image pixels (160x64" in listing["pixel_frame"]
    rows = listing["objects"]
    assert [r["id"] for r in rows] == truth.objects.instance_id.tolist()  # gt proposals: the frame's objects
    assert all(set(r) == FIELDS for r in rows) and all(r["class"] in ("Car", "Van") for r in rows)
    boxes = (mask_boxes(truth.objects.mask) * 2).tolist()  # working-size boxes scaled to the 160x64 input
    assert [r["box"] for r in rows] == boxes
    intr = record.intrinsics  # the camera at the stored (input) size
    assert (intr.width, intr.height) == (160, 64)
    with_geometry = [r for r in rows if r["template"] is not None]
    assert with_geometry
    for r in with_geometry:
        x, y, z = r["xyz_m"]
        u, v = intr.fx * x / z + intr.cx, intr.fy * y / z + intr.cy  # projected with the input camera
        assert r["centre"] == pytest.approx([u, v], abs=0.06)
        assert r["distance_m"] == pytest.approx(float(np.linalg.norm([x, y, z])), abs=0.01)


def test_list_prints_a_table(tiny_synth, ckpts, tmp_path, capsys):
    (tmp_path / "empty.yaml").write_text("# nothing yet\n")
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out, f"edits={tmp_path / 'empty.yaml'}")) == 0  # an empty spec lists
    printed = capsys.readouterr().out
    assert "input-image pixels (160x64" in printed and "box x0 y0 x1 y1" in printed
    rows = json.loads((out / "objects.json").read_text())["objects"]
    for r in rows:
        assert any(line.split()[:2] == [str(r["id"]), r["class"]] for line in printed.splitlines())
    picture = np.asarray(Image.open(out / "objects.png"))
    assert picture.shape[1:] == (160, 3) and picture.shape[0] > 64  # the input's width, plus a title band
    assert not (out / "edited.png").exists()
    assert main(_args(tiny_synth, ckpts, out, "list=true")) == 0  # overwrite=true replaces an earlier listing


def test_image_file_listing_is_in_the_files_pixels(ckpts, tiny_synth, tmp_path):
    rgb = vkitti1.load_rgb(vkitti1.read_frames(tiny_synth)[4])
    Image.fromarray(np.ascontiguousarray(rgb)).resize((320, 128)).save(tmp_path / "street.png")
    out = tmp_path / "out"
    args = [f"input.image={tmp_path / 'street.png'}", "image_size=[160,64]", "list=true",
            "input.intrinsics={fx:187,fy:247,cx:159.5,cy:63.5}",  # 320x128 is not Virtual KITTI's camera
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", f"output_dir={out}"]
    assert main(args) == 0
    listing = json.loads((out / "objects.json").read_text())
    assert listing["input_size"] == [320, 128] and listing["working_size"] == [160, 64]
    for r in listing["objects"]:
        if r["box"] is not None:
            x0, y0, x1, y1 = r["box"]
            assert 0 <= x0 < x1 <= 320 and 0 <= y0 < y1 <= 128
    assert np.asarray(Image.open(out / "objects.png")).shape[1] == 320


def test_no_edits_and_no_list_is_a_user_error(tiny_synth, ckpts, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(_args(tiny_synth, ckpts, out)) == 2
    err = capsys.readouterr().err
    assert err.startswith("sdn3d-edit: error: give an edit spec") and "list=true" in err and not out.exists()
    assert main(_args(tiny_synth, ckpts, out, "list=maybe")) == 2
    assert "list must be true or false" in capsys.readouterr().err


def test_the_table_lists_a_proposal_beside_box_objects():
    """A semantic proposal has no fit record of a box; listed beside box objects, its fit cells are empty (it raised
    KeyError: 'fit_iou')."""
    from sdn3d.scene.listing import objects_table

    common = {"class": "Car", "box": [1, 2, 30, 20], "centre": [15.0, 11.0], "distance_m": 12.5, "yaw_deg": -90.0,
              "template": "sedan"}
    table = objects_table([{"id": 12001, **common, "fit_iou": 0.91}, {"id": 12002, **common}])
    box_row, proposal_row = table.splitlines()[1:]
    assert box_row.split()[-4:] == ["0.91", "from", "a", "box"] and proposal_row.split()[-2:] == ["-", "-"]
