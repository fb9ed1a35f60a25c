"""Issue 32, one writer per output: a lock file (pid, host, start time) makes a second ``sdn3d-edit`` into the same
``output_dir``, or a second ``sdn3d-train`` into the same run directory, stop with a clear error before it writes
anything; a lock left by a killed process is stale and replaced. Before, both writers reported success."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.tiny_models import write_checkpoints
from hydra import compose, initialize_config_dir

from sdn3d.cli.edit import main as edit_main
from sdn3d.io import BusyError, owner_record, writer_lock

REPO = Path(__file__).resolve().parents[1]
FRAME = "0001/clone/00004"


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def _stale_lock(path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(owner_record() | {"pid": _dead_pid(), "start": None, "started": "earlier"}))
    return path


def test_a_second_writer_is_refused_naming_the_holder(tmp_path):
    lock = tmp_path / "out.lock"
    with writer_lock(lock, "output_dir 'out'"):
        record = json.loads(lock.read_text())
        assert record["pid"] == owner_record()["pid"] and record["host"] and record["started"]
        with pytest.raises(BusyError, match=rf"output_dir 'out' is being written by another sdn3d process \(pid "
                                            rf"{record['pid']} .*lock file '{lock}'"):
            with writer_lock(lock, "output_dir 'out'"):
                pass
        assert lock.is_file()
    assert not lock.exists()


def test_a_stale_lock_is_replaced_and_an_unreadable_one_is_not(tmp_path):
    lock = _stale_lock(tmp_path / "out.lock")
    with writer_lock(lock, "out"):
        assert json.loads(lock.read_text())["pid"] == owner_record()["pid"]
    assert not lock.exists()
    lock.write_text("{not json")
    with pytest.raises(BusyError, match="an unreadable lock record.*delete the lock file"):
        with writer_lock(lock, "out"):
            pass
    assert lock.read_text() == "{not json"
    lock.write_text(json.dumps(owner_record() | {"host": "another-host"}))
    with pytest.raises(BusyError, match="on host 'another-host'"):
        with writer_lock(lock, "out"):
            pass


def test_sdn3d_edit_refuses_an_output_dir_another_run_is_writing(tmp_path, capsys):
    out = tmp_path / "out"
    spec = tmp_path / "ops.yaml"
    spec.write_text("- {op: delete, id: 12001}\n")
    with writer_lock(tmp_path / ".out.lock", f"output_dir {str(out)!r}"):
        assert edit_main([f"edits={spec}", f"output_dir={out}"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "is being written by another sdn3d process" in err, err
    assert not out.exists()


def test_sdn3d_edit_replaces_a_killed_runs_lock(tiny_synth, tmp_path):
    ckpts = write_checkpoints(tmp_path / "ckpt")
    out = tmp_path / "out"
    lock = _stale_lock(tmp_path / ".out.lock")
    spec = tmp_path / "ops.yaml"
    spec.write_text("- {op: recolor, class: Sky, code: [0, 0, 0, 0, 1]}\n")
    args = ["data=synth", f"data.root={tiny_synth}", "data.image_size=[160,64]", f"edits={spec}",
            *(f"checkpoints.{k}={v}" for k, v in ckpts.items()), "geometric.crop_size=32", "proposals=gt",
            f"output_dir={out}", f"input.frame={FRAME}"]
    assert edit_main(args) == 0
    assert (out / "edit.json").is_file() and not lock.exists()


def test_sdn3d_train_refuses_a_run_directory_another_training_writes(tiny_synth, tmp_path):
    from lightning_modules.train import run_training
    from sdn3d.training.locks import RUN_LOCK

    run_dir = tmp_path / "run"
    overrides = ["branch=semantic", "experiment=demo", f"data.root={tiny_synth}", "data.image_size=[160,64]",
                 f"run_dir={run_dir}", f"summary_file={tmp_path / 'summary.jsonl'}", "trainer.max_epochs=1",
                 "logger=none"]
    with initialize_config_dir(config_dir=str(REPO / "conf"), version_base="1.3"):
        cfg = compose("train", overrides=overrides)
    with writer_lock(run_dir / RUN_LOCK, f"run directory {str(run_dir)!r}"):
        with pytest.raises(BusyError, match=r"run directory .* is being written by another sdn3d process"):
            run_training(cfg, overrides)
        assert sorted(p.name for p in run_dir.iterdir()) == [RUN_LOCK]  # no config.yaml, no summary, no log
    assert not (tmp_path / "summary.jsonl").exists()
