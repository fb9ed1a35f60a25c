"""Issue 32, bounded inputs: small inputs may not cost large amounts of time, memory or output.

YAML anchors and aliases are refused before anything is built (a 400-byte alias bomb expanded to gigabytes and
its error message echoed it), error messages quote at most a short excerpt of a value, an edit spec holds at most
``max_ops`` operations, ``ry_deg`` is bounded like ``ry_rad``, ``threads`` / ``pick_radius`` / ``max_ops`` are
checked, an output directory that cannot be written is refused before the work starts, staging trees left by a
killed edit are removed, and ``Duplicate`` ops are appended to the scene in one concatenation (it was one per op:
quadratic)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time

import pytest
import torch
from helpers.tiny_models import write_checkpoints

from sdn3d.cli.edit import main as edit_main
from sdn3d.editing.apply import Delete, Duplicate, Move, apply_edits
from sdn3d.editing.spec import EXCERPT_CHARS, MAX_OPS, EditSpecError, load_edit_spec, parse_edit_spec
from sdn3d.io import OWNER_FILE, owner_record
from sdn3d.math3d.camera import Intrinsics
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject

FRAME = "0001/clone/00004"


def _spec(tmp_path, text, name="ops.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _edit_error(capsys, args) -> str:
    assert edit_main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("sdn3d-edit: error: ") and len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


# -- YAML aliases, excerpts, huge values -------------------------------------------------------------------


def test_yaml_aliases_are_refused(tmp_path):
    path = _spec(tmp_path, "- &a {op: delete, id: 12001}\n- *a\n")
    with pytest.raises(EditSpecError, match=r"ops.yaml:1: .*anchors and aliases"):
        load_edit_spec(path)


def test_a_yaml_alias_bomb_is_refused_at_once_with_a_short_message(tmp_path, capsys):
    lines = ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for level in "bcdefghi":  # 9^9 = 387 million strings once expanded
        previous = chr(ord(level) - 1)
        lines.append(f"{level}: &{level} [" + ", ".join([f"*{previous}"] * 9) + "]")
    path = _spec(tmp_path, "\n".join(lines) + "\nops: *i\n")
    assert path.stat().st_size < 1000
    start = time.perf_counter()
    with pytest.raises(EditSpecError, match="anchors and aliases") as info:
        load_edit_spec(path)
    assert time.perf_counter() - start < 2.0 and len(str(info.value)) < 300
    err = _edit_error(capsys, [f"edits={path}", f"output_dir={tmp_path / 'out'}", "input.image=x.png"])
    assert len(err) < 400 and "anchors and aliases" in err


def test_a_moderate_alias_expansion_is_not_echoed_in_the_message(tmp_path):
    levels = ['&a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for level in "bcde":  # 59049 strings: before, the message echoed them all (about 0.5 MB)
        levels.append(f"&{level} [" + ", ".join([f"*{chr(ord(level) - 1)}"] * 9) + "]")
    path = _spec(tmp_path, "- {op: rotate, id: 12001, ry_deg: [" + ", ".join(levels) + "]}\n")
    with pytest.raises(EditSpecError) as info:
        load_edit_spec(path)
    assert len(str(info.value)) < 300


@pytest.mark.parametrize("text, field", [
    ("- {op: move, id: 12001, to: '" + "x" * 1_000_000 + "'}\n", "'to'"),
    ("- {op: '" + "m" * 1_000_000 + "', id: 12001}\n", "'op'"),
    ("- {op: recolor, id: 12001, color: '" + "r" * 1_000_000 + "'}\n", "'color'"),
    ("- {op: zoom, id: 12001, zoom: [" + ", ".join(["1"] * 20_000) + "]}\n", "'zoom'"),
    ("- {op: delete, id: 12001, " + ", ".join(f"k{i}: 1" for i in range(5_000)) + "}\n", "unknown field"),
])
def test_error_messages_quote_a_short_excerpt_of_a_value(tmp_path, text, field):
    with pytest.raises(EditSpecError, match=field) as info:
        load_edit_spec(_spec(tmp_path, text))
    assert len(str(info.value)) < len(str(tmp_path)) + 250 + EXCERPT_CHARS, len(str(info.value))


def test_an_integer_too_long_to_print_is_an_edit_spec_error(tmp_path):
    path = _spec(tmp_path, "- {op: delete, id: " + "9" * 20_000 + "}\n")
    with pytest.raises(EditSpecError) as info:
        load_edit_spec(path)
    assert str(path) in str(info.value) and len(str(info.value)) < 400


# -- how many ops, angles ------------------------------------------------------------------------------


def test_the_number_of_ops_is_capped(tmp_path, capsys):
    ops = [{"op": "delete", "id": 12001}] * (MAX_OPS + 1)
    with pytest.raises(EditSpecError, match=rf"{MAX_OPS + 1} edit operations, more than max_ops={MAX_OPS}"):
        parse_edit_spec(ops, "ops.yaml")
    assert len(parse_edit_spec(ops, "ops.yaml", max_ops=None)) == MAX_OPS + 1
    path = _spec(tmp_path, "- {op: delete, id: 12001}\n- {op: delete, id: 12002}\n")
    assert "max_ops=1" in _edit_error(capsys, [f"edits={path}", f"output_dir={tmp_path / 'out'}", "max_ops=1",
                                               "input.image=x.png"])


@pytest.mark.parametrize("value", ["1e308", "361", "-400", "1.0e+300"])
def test_ry_deg_is_bounded_like_ry_rad(value):
    with pytest.raises(EditSpecError, match=r"'ry_deg' is .* degrees, more than a full turn \(360\)"):
        parse_edit_spec([{"op": "rotate", "id": 12001, "ry_deg": value}])


def test_ry_deg_within_a_turn_is_accepted():
    for degrees in (360, -360, 45.5):
        assert parse_edit_spec([{"op": "rotate", "id": 12001, "ry_deg": degrees}]).ops[0].ry == pytest.approx(
            math.radians(degrees))


# -- settings ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("override, setting", [("threads=-3", "threads"), ("threads=0", "threads"),
                                               ("threads=2.5", "threads"), ("threads=true", "threads"),
                                               ("pick_radius=-1", "pick_radius"), ("pick_radius=nan", "pick_radius"),
                                               ("pick_radius=0", "pick_radius"), ("pick_radius=inf", "pick_radius"),
                                               ("max_ops=0", "max_ops")])
def test_bad_thread_counts_and_radii_are_refused_by_name(tmp_path, capsys, override, setting):
    path = _spec(tmp_path, "- {op: delete, id: 12001}\n")
    threads = torch.get_num_threads()
    err = _edit_error(capsys, [f"edits={path}", f"output_dir={tmp_path / 'out'}", override])
    assert f"error: {setting} must be" in err
    assert torch.get_num_threads() == threads


def test_an_output_dir_that_cannot_be_written_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    import sdn3d.cli.edit as edit

    def no_work(*args, **kwargs):
        raise AssertionError("the work started")

    monkeypatch.setattr(edit, "resolve_checkpoints", no_work)
    monkeypatch.setattr(edit, "load_input", no_work)
    path = _spec(tmp_path, "- {op: delete, id: 12001}\n")
    err = _edit_error(capsys, [f"edits={path}", "output_dir=/proc/sdn3d-no-such/out"])
    assert "output_dir '/proc/sdn3d-no-such/out' cannot be written" in err


# -- staging leftovers of a killed edit ---------------------------------------------------------------------


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_staging_trees_of_a_killed_edit_are_removed(tiny_synth, tmp_path):
    ckpts = write_checkpoints(tmp_path / "ckpt")
    out = tmp_path / "out"
    dead, live = tmp_path / ".out.partial-killed", tmp_path / ".out.partial-running"
    for tree, record in ((dead, owner_record() | {"pid": _dead_pid(), "start": None}), (live, owner_record())):
        (tree / "maps").mkdir(parents=True)
        (tree / "maps" / "half.png").write_bytes(b"x")
        (tree / OWNER_FILE).write_text(json.dumps(record))
    path = _spec(tmp_path, "- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    args = ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"edits={path}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", "proposals=gt",
            f"output_dir={out}", f"input.frame={FRAME}"]
    assert edit_main(args) == 0
    assert not dead.exists() and live.is_dir() and (out / "edit.json").is_file()
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".out.")) == [live.name]


# -- Duplicate is linear --------------------------------------------------------------------------------


def _scene(height=24, width=64) -> SceneCode:
    car = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), location=(0.0, 1.6, 12.0))
    return SceneCode(Intrinsics(60.0, 60.0, 31.5, 11.5, width=width, height=height),
                     torch.zeros(height, width, dtype=torch.long), "vkitti",
                     ObjectTable.from_objects([car], height, width), background_codes={})


def test_duplicates_are_appended_in_one_concatenation(monkeypatch):
    scene = _scene()
    copied = []
    real_cat = torch.cat

    def counting_cat(tensors, *args, **kwargs):
        result = real_cat(tensors, *args, **kwargs)
        if result.dtype == torch.bool and result.dim() == 3 and tuple(result.shape[1:]) == (24, 64):
            copied.append(result.numel())
        return result

    monkeypatch.setattr(torch, "cat", counting_cat)
    n = 200
    ops = [Duplicate(12001, (2.0 + 0.3 * k, 20.0)) for k in range(n)]
    edited = apply_edits(scene, ops)
    monkeypatch.setattr(torch, "cat", real_cat)
    assert edited.objects.instance_id.tolist() == [12001 + k for k in range(n + 1)]
    # one table of n + 1 masks is built (before: one concatenation per op, n (n + 1) / 2 masks copied)
    assert sum(copied) <= 2 * (n + 1) * 24 * 64, sum(copied) / (24 * 64)


def test_duplicates_named_by_later_ops_are_in_place_when_those_run():
    scene = _scene()
    ops = [Duplicate(12001, (40.0, 18.0), new_id=12050), Duplicate(12001, (20.0, 18.0)),
           Move(12050, (50.0, 20.0)), Duplicate(12050, (10.0, 20.0)), Delete(12051)]
    edited = apply_edits(scene, ops)
    assert edited.objects.instance_id.tolist() == [12001, 12050, 12052]
    moved = apply_edits(scene, ops[:1] + [Move(12050, (50.0, 20.0))]).objects
    assert torch.equal(edited.objects.location[1], moved.location[1])
    with pytest.raises(Exception, match="new id 12050 must be a free id"):
        apply_edits(scene, [Duplicate(12001, (40.0, 18.0), new_id=12050), Duplicate(12001, (30.0, 18.0),
                                                                                    new_id=12050)])
