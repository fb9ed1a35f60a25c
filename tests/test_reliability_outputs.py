"""Issue 32, "never delete what the program did not write": an edit ``output_dir`` is replaced only when it holds
nothing but the files its earlier run listed in ``edit.json`` (``outputs``), never when it holds one of the run's
inputs; ``sdn3d-export-weights`` refuses an existing OUT unless ``--overwrite`` and a training checkpoint always."""

from __future__ import annotations

import json

import pytest
import torch
from helpers.tiny_models import write_checkpoints

from sdn3d.cli.edit import main as edit_main
from sdn3d.cli.export_weights import main as export_main
from sdn3d.io import OutputDirError, check_output_dir, file_sha256

FRAME = "0001/clone/00004"


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def _args(tiny_synth, ckpts, out, edits, *extra):
    return ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"edits={edits}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32",
            "geometric.min_pixels=1", "proposals=gt", f"output_dir={out}", f"input.frame={FRAME}", *extra]


@pytest.fixture
def earlier(tiny_synth, ckpts, tmp_path):
    """An output_dir holding an earlier edit's outputs, and the arguments that made it."""
    edits = tmp_path / "ops.yaml"
    edits.write_text("- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    out = tmp_path / "out"
    args = _args(tiny_synth, ckpts, out, edits)
    assert edit_main(args) == 0
    return out, args


def _err(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert err.startswith("sdn3d-edit: error: ") and len(err.splitlines()) == 1, err
    return err


# -- the rule, in sdn3d.io -----------------------------------------------------------------------------


def test_check_output_dir_replaces_only_what_the_marker_lists(tmp_path):
    out = tmp_path / "out"
    (out / "maps").mkdir(parents=True)
    (out / "a.png").write_bytes(b"a")
    (out / "maps" / "b.png").write_bytes(b"b")
    (out / "edit.json").write_text(json.dumps({"outputs": ["a.png", "maps/b.png", "edit.json"]}))
    assert check_output_dir(out, "edit.json", True, listed_in="outputs") == out.resolve()
    (out / "maps" / "notes.txt").write_text("mine")
    with pytest.raises(OutputDirError, match=r"1 entry the earlier run did not write \('maps/notes.txt'"):
        check_output_dir(out, "edit.json", True, listed_in="outputs")
    (out / "maps" / "notes.txt").unlink()
    (out / "photos").mkdir()
    with pytest.raises(OutputDirError, match=r"'photos/'"):
        check_output_dir(out, "edit.json", True, listed_in="outputs")
    (out / "photos").rmdir()
    (out / "link").symlink_to(tmp_path)
    with pytest.raises(OutputDirError, match=r"'link'"):
        check_output_dir(out, "edit.json", True, listed_in="outputs")


def test_check_output_dir_refuses_a_marker_that_lists_nothing(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "edit.json").write_text("{}")
    with pytest.raises(OutputDirError, match=r"does not list the files the earlier run wrote"):
        check_output_dir(out, "edit.json", True, listed_in="outputs")


def test_check_output_dir_refuses_when_an_input_lives_inside(tmp_path):
    out = tmp_path / "out"
    (out / "sub").mkdir(parents=True)
    (out / "edit.json").write_text(json.dumps({"outputs": ["sub/photo.png", "edit.json"]}))
    (out / "sub" / "photo.png").write_bytes(b"x")
    with pytest.raises(OutputDirError, match=r"input.image .*photo.png.* lies inside output_dir"):
        check_output_dir(out, "edit.json", True, listed_in="outputs",
                         inputs={"input.image": str(out / "sub" / "photo.png"), "edits": None})
    assert check_output_dir(tmp_path / "new", "edit.json", True, inputs={"input.image": str(out / "x")})


# -- sdn3d-edit ----------------------------------------------------------------------------------------


def test_edit_does_not_delete_a_users_file_in_output_dir(earlier, capsys):
    out, args = earlier
    before = (out / "edit.json").read_bytes()
    (out / "notes.txt").write_text("keep me")
    assert edit_main(args) == 2
    err = _err(capsys)
    assert "'notes.txt'" in err and "did not write" in err
    assert (out / "notes.txt").read_text() == "keep me" and (out / "edit.json").read_bytes() == before


def test_edit_does_not_delete_its_own_inputs_inside_output_dir(earlier, capsys):
    out, args = earlier
    picture = out / "edited.png"  # an earlier result, listed in its edit.json, given as this run's input
    before = picture.read_bytes()
    camera = "input.intrinsics={fx:93.0,fy:124.0,cx:79.5,cy:31.5}"
    assert edit_main([*args, f"input.image={picture}", camera]) == 2
    err = _err(capsys)
    assert "input.image" in err and "lies inside output_dir" in err
    assert picture.read_bytes() == before
    spec = out / "ops.yaml"
    spec.write_text("- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    assert edit_main([*args, f"edits={spec}"]) == 2  # the later override wins
    assert "edits" in _err(capsys) and spec.is_file()


def test_edit_replaces_an_earlier_edit_or_listing_of_its_own(earlier, capsys):
    out, args = earlier
    listing = [a for a in args if not a.startswith("edits=")] + ["list=true"]
    assert edit_main(listing) == 0
    assert json.loads((out / "edit.json").read_text())["mode"] == "list"
    assert edit_main(args) == 0  # the listing's files are all in its edit.json: replaced
    summary = json.loads((out / "edit.json").read_text())
    assert "mode" not in summary and sorted(p.name for p in out.iterdir() if p.is_file()) == sorted(
        n for n in summary["outputs"] if "/" not in n)
    assert ".sdn3d-owner.json" not in summary["outputs"]


# -- sdn3d-export-weights ----------------------------------------------------------------------------------


def _training_checkpoint(path, ckpts):
    content = torch.load(ckpts["semantic"], weights_only=True)
    content |= {"pytorch-lightning_version": "2.4.0", "optimizer_states": [], "epoch": 3, "global_step": 12}
    torch.save(content, path)
    return path


def test_export_weights_refuses_an_existing_out_unless_overwrite(ckpts, tmp_path, capsys):
    out = tmp_path / "mine.pt"
    out.write_text("a user's file")
    assert export_main([str(ckpts["semantic"]), str(out)]) == 2
    err = capsys.readouterr().err
    assert "exists" in err and "--overwrite" in err and out.read_text() == "a user's file"
    assert export_main([str(ckpts["semantic"]), str(out), "--overwrite"]) == 0
    assert torch.load(out, weights_only=True)["format"] == "sdn3d-inference-weights"


def test_export_weights_never_overwrites_a_training_checkpoint(ckpts, tmp_path, capsys):
    last = _training_checkpoint(tmp_path / "last.ckpt", ckpts)
    digest = file_sha256(last)
    for extra in ([], ["--overwrite"]):
        assert export_main([str(ckpts["geometric"]), str(last), *extra]) == 2
        err = capsys.readouterr().err
        assert "is a training checkpoint" in err and "resume" in err, err
    assert file_sha256(last) == digest


def test_export_weights_default_out_replaces_its_own_export(ckpts, tmp_path, capsys):
    (tmp_path / "run").mkdir()
    ckpt = _training_checkpoint(tmp_path / "run" / "last.ckpt", ckpts)
    assert export_main([str(ckpt)]) == 0
    assert export_main([str(ckpt)]) == 0  # inference.pt beside it is this tool's own: refreshed
    (tmp_path / "run" / "inference.pt").write_text("not an export")
    assert export_main([str(ckpt)]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert (tmp_path / "run" / "inference.pt").read_text() == "not an export"
