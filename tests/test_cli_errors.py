"""How the command-line tools report errors: a user's mistake is one line and exit status 2
(sdn3d.cli._errors.run_cli); any other exception, a plain ValueError included, keeps its traceback."""

from __future__ import annotations

import subprocess
import sys

import pytest
from hydra import compose, initialize_config_dir

from sdn3d.cli._config import CONFIG_DIR
from sdn3d.cli._errors import run_cli
from sdn3d.errors import InputError, UserInputError


def _one_error_line(err: str, tool: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"sdn3d-{tool}: error: "), err
    return lines[0]


def _error_report(err: str, tool: str) -> str:
    """A message that is not ours (OmegaConf, Hydra) may add indented detail lines; still no traceback."""
    assert err.startswith(f"sdn3d-{tool}: error: ") and "Traceback" not in err, err
    return err


def _compose(name: str, overrides: list[str]):
    with initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
        return compose(name, overrides=overrides)


def _raise(exc: BaseException):
    def fn(*args, **kwargs):
        raise exc

    return fn


# -- the error classes ----------------------------------------------------------------------------


def test_user_facing_errors_derive_from_user_input_error():
    from sdn3d.cli.table2 import SummaryError
    from sdn3d.data.errors import DataFormatError, MissingDataError
    from sdn3d.editing.ops import EditError
    from sdn3d.editing.spec import EditSpecError
    from sdn3d.nets.weights import PretrainedWeightsError
    from sdn3d.scene.code import SceneFormatError

    for cls in (DataFormatError, MissingDataError, EditError, EditSpecError, SceneFormatError,
                PretrainedWeightsError, InputError, SummaryError):
        assert issubclass(cls, UserInputError) and issubclass(cls, ValueError), cls
    assert issubclass(MissingDataError, FileNotFoundError)


def test_training_error_is_a_user_error_and_still_a_runtime_error():
    from sdn3d.training.errors import TrainingError

    assert issubclass(TrainingError, UserInputError) and issubclass(TrainingError, RuntimeError)


# -- run_cli ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("exc", [InputError("bad setting x=1; use x=2"), FileNotFoundError("no such file: a.png"),
                                 FileExistsError("output_dir 'o' is not empty"), PermissionError("o: not writable")])
def test_run_cli_reports_user_mistakes_in_one_line(capsys, exc):
    assert run_cli("tool", _raise(exc)) == 2
    assert _one_error_line(capsys.readouterr().err, "tool") == f"sdn3d-tool: error: {exc}"


def test_run_cli_reports_config_errors(capsys):
    from omegaconf import OmegaConf

    cfg = OmegaConf.create({"a": "???"})
    assert run_cli("tool", lambda: cfg.a) == 2
    assert "Missing mandatory value: a" in _error_report(capsys.readouterr().err, "tool")


@pytest.mark.parametrize("exc", [ValueError("a bug"), RuntimeError("a bug"), KeyError("a bug")])
def test_run_cli_lets_other_errors_propagate(capsys, exc):
    with pytest.raises(type(exc), match="a bug"):
        run_cli("tool", _raise(exc))
    assert capsys.readouterr().err == ""


def test_run_cli_passes_the_exit_status_through():
    assert run_cli("tool", lambda: None) == 0
    assert run_cli("tool", lambda x: x, 1) == 1


# -- each tool: a user mistake is one line and exit 2; a plain ValueError from inside is not ----------


def test_edit(tmp_path, capsys, monkeypatch):
    import sdn3d.cli.edit as edit

    (tmp_path / "ops.yaml").write_text("- {op: delete, id: 12001}\n")
    args = [f"edits={tmp_path / 'ops.yaml'}", f"output_dir={tmp_path / 'out'}"]
    assert edit.main([*args, "proposals=everything"]) == 2
    assert "proposals must be one of auto, gt, semantic, boxes" in _one_error_line(capsys.readouterr().err, "edit")
    assert edit.main([*args, "no_such_key=1"]) == 2
    assert "bad configuration override" in _error_report(capsys.readouterr().err, "edit")
    monkeypatch.setattr(edit, "load_input", _raise(ValueError("a bug while loading the image")))
    with pytest.raises(ValueError, match="a bug while loading the image") as info:
        edit.main(args)
    assert not isinstance(info.value, UserInputError) and capsys.readouterr().err == ""
    assert not (tmp_path / "out").exists()


def test_bench(tmp_path, capsys, monkeypatch):
    import sdn3d.cli.bench as bench

    args = [f"data.root={tmp_path / 'no_data'}", f"output_dir={tmp_path / 'out'}"]
    assert bench.main(args) == 2
    assert "edit benchmark file not found" in _one_error_line(capsys.readouterr().err, "bench")
    monkeypatch.setattr(bench, "run_bench", _raise(ValueError("a bug in the benchmark")))
    with pytest.raises(ValueError, match="a bug in the benchmark"):
        bench.main(args)


def test_table2(tmp_path, capsys, monkeypatch):
    import sdn3d.cli.table2 as table2

    assert table2.main(["--out", str(tmp_path / "out")]) == 2
    assert "give at least one --summary" in _one_error_line(capsys.readouterr().err, "table2")
    (tmp_path / "s.jsonl").write_text("")
    args = ["--summary", str(tmp_path / "s.jsonl"), "--out", str(tmp_path / "out")]
    monkeypatch.setattr(table2, "group_runs", _raise(ValueError("a bug in group_runs")))
    with pytest.raises(ValueError, match="a bug in group_runs"):
        table2.main(args)
    assert not (tmp_path / "out").exists()


def test_synth(tmp_path, capsys, monkeypatch):
    import sdn3d.cli.synth as synth

    cfg = _compose("synth", [f"output_dir={tmp_path / 'data'}", "frames_per_sequence=0"])
    with pytest.raises(SystemExit) as info:
        synth.main(cfg)  # a composed config passes through @hydra.main
    assert info.value.code == 2
    assert "frames_per_sequence must be >= 1" in _one_error_line(capsys.readouterr().err, "synth")
    monkeypatch.setattr(synth, "generate_dataset", _raise(ValueError("a bug in the generator")))
    with pytest.raises(ValueError, match="a bug in the generator"):
        synth.main(_compose("synth", [f"output_dir={tmp_path / 'data'}"]))
    assert not (tmp_path / "data").exists()


def test_synth_console_entry_point_exits_2(tmp_path):
    """The real entry point through Hydra: exit status 2 and one line on stderr, no traceback."""
    proc = subprocess.run(
        [sys.executable, "-m", "sdn3d.cli.synth", f"output_dir={tmp_path / 'data'}", "worlds=[1]",
         f"hydra.run.dir={tmp_path / 'hydra'}"], capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    assert "worlds must be a non-empty list of 4-digit names" in _one_error_line(proc.stderr, "synth")
    assert not (tmp_path / "data").exists()


def test_render_demo(tmp_path, capsys, monkeypatch):
    import sdn3d.cli.render_demo as render_demo

    overrides = [f"output_dir={tmp_path / 'demo'}", f"data_dir={tmp_path / 'data'}", "threads=1"]
    with pytest.raises(SystemExit) as info:
        render_demo.main(_compose("render_demo", [*overrides, "synth.frames_per_sequence=0"]))
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert "frames_per_sequence must be >= 1" in _one_error_line(err[err.index("sdn3d-render-demo"):], "render-demo")
    monkeypatch.setattr(render_demo, "_generate_data", _raise(ValueError("a bug in stage 1")))
    with pytest.raises(ValueError, match="a bug in stage 1"):
        render_demo.main(_compose("render_demo", overrides))
