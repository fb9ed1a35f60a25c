"""Issue 42, item 5: sdn3d-edit checks the spec as early as it can (points before any model, the ids of box objects
before the de-render) and says on stderr what it is doing, stage by stage, with the seconds each took."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers.tiny_models import write_checkpoints

import sdn3d.derender
from sdn3d.cli import edit as edit_cli
from sdn3d.cli.edit import main
from sdn3d.editing.spec import box_object_ids, check_ids, parse_edit_spec

REAL = Path(__file__).resolve().parent / "data" / "0006_30-deg-right_00043.png"
BOXES = "objects:\n  - {box: [466, 203, 666, 333], class: Car}\n  - {box: [704, 194, 917, 305], class: Car}\n"


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


def _cli(ckpts, tmp_path, ops: str, name: str = "out"):
    spec = tmp_path / f"{name}.yaml"
    spec.write_text(BOXES + "ops:\n" + ops)
    return main([f"input.image={REAL}", f"edits={spec}", "proposals=boxes",
                 f"checkpoints.geometric={ckpts['geometric']}", f"checkpoints.textural={ckpts['textural']}",
                 "geometric.crop_size=32", "image_size=[312,96]", f"output_dir={tmp_path / name}", "progress=true"])


def test_a_bad_id_of_a_box_object_is_refused_before_the_derender(ckpts, tmp_path, capsys, monkeypatch):
    def no_derender(*args, **kwargs):
        raise AssertionError("de-rendered before the ids were checked")

    monkeypatch.setattr(sdn3d.derender, "derender", no_derender)
    assert _cli(ckpts, tmp_path, "  - {op: duplicate, id: 12002, to: [300, 330]}\n"
                                 "  - {op: rotate, id: 12003, ry_deg: 30}\n  - {op: delete, id: 12005}\n") == 2
    err = capsys.readouterr().err
    assert ("op 2 (delete id=12005): no object with id 12005 (the scene will have [12001, 12002, 12003]: with "
            "proposals=boxes the objects are the spec's boxes, in their order; checked before the de-render)") in err
    assert "de-rendering" not in err


def test_a_point_outside_the_picture_is_refused_before_any_model_loads(ckpts, tmp_path, capsys, monkeypatch):
    def no_models(*args, **kwargs):
        raise AssertionError("loaded the models before the points were checked")

    monkeypatch.setattr(edit_cli, "load_models", no_models)
    assert _cli(ckpts, tmp_path, "  - {op: move, id: 12001, to: [1300, 300]}\n") == 2
    err = capsys.readouterr().err
    assert "op 0 (move id=12001): 'to' point [1300.0, 300.0] lies outside the 1242x375 frame" in err
    assert "loading the models" not in err


def test_each_stage_says_what_it_does_and_how_long_it_took(ckpts, tmp_path, capsys):
    """And the copy a duplicate makes can be turned by the next op (issue 42, item 1), through the command line."""
    assert _cli(ckpts, tmp_path, "  - {op: duplicate, id: 12002, to: [1000, 300]}\n"
                                 "  - {op: rotate, id: 12003, ry_deg: 30}\n") == 0
    err = capsys.readouterr().err
    for stage in (r"loading the models", r"de-rendering \(2 boxes\)", r"editing and drawing \(2 ops\)",
                  r"writing the outputs"):
        assert re.search(rf"^sdn3d-edit: {stage}\.\.\. \d+\.\d s$", err, re.M), (stage, err)


def test_check_ids_follows_the_ops():
    assert box_object_ids([12, 12, 13]) == [12001, 12002, 13001]
    assert box_object_ids([12], taken=[12004, 13001]) == [12005]
    spec = parse_edit_spec([{"op": "delete", "id": 12001}, {"op": "duplicate", "id": 12002, "to": [1, 1]},
                            {"op": "rotate", "id": 12003, "ry_deg": 5}, {"op": "rotate", "id": 12001, "ry_deg": 5}])
    with pytest.raises(Exception, match=r"op 3 \(rotate id=12001\): no object with id 12001 \(the scene will have "
                                        r"\[12002, 12003\]\)"):
        check_ids(spec, [12001, 12002])
    # after a delete by position, which object is gone is unknown: nothing more is checked
    check_ids(parse_edit_spec([{"op": "delete", "at": [5, 5]}, {"op": "rotate", "id": 99001, "ry_deg": 5}]), [12001])


def test_the_apps_start_up_lines_say_sdn3d_app(ckpts, tmp_path, capsys):
    """run= picks each branch's checkpoint and says so on stderr: under sdn3d-app, as sdn3d-app (issue 42)."""
    import json
    import shutil

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.edit import resolve_checkpoints

    for branch in ("semantic", "geometric", "textural"):
        run = tmp_path / "runs" / branch
        (run / "checkpoints").mkdir(parents=True)
        last = shutil.copy(ckpts[branch], run / "checkpoints" / "last.ckpt")
        (run / "summary.json").write_text(json.dumps({"branch": branch, "run_dir": str(run), "best_ckpt": None,
                                                      "last_ckpt": str(last), "status": "ok",
                                                      "finished": "2026-01-01T10:00:00+00:00"}))
    (tmp_path / "runs" / "summary.jsonl").write_text("")
    resolve_checkpoints(compose_config([f"run={tmp_path}"], "app"))
    app_err = capsys.readouterr().err
    resolve_checkpoints(compose_config([f"run={tmp_path}"], "edit"))
    edit_err = capsys.readouterr().err
    assert app_err.startswith("sdn3d-app: ") and "sdn3d-edit" not in app_err, app_err
    assert edit_err.startswith("sdn3d-edit: ") and edit_err.replace("sdn3d-edit", "sdn3d-app") == app_err
