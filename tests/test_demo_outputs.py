"""Issue 42 (3): re-running ``sdn3d-demo`` on a finished output keeps what it does not replace.

Before: ``train_branch`` deleted ``runs/<branch>`` before training again, so a failed or interrupted re-run left no
weights; ``make_data`` regenerated ``data/`` with overwrite forced, deleting a user's files there. Now: the earlier
run waits in ``runs/.<branch>.previous`` and is removed only once the new run finished ok, else put back; the data
are reused when generated with the same settings, and a data directory holding a file the generator did not write
is refused naming it."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from omegaconf import OmegaConf

import sdn3d.cli.demo as demo
from sdn3d.errors import InputError


def _cfg(tmp_path: Path) -> object:
    return OmegaConf.create({"data_dir": str(tmp_path / "data"), "seed": 0, "threads": 1, "workers": 0,
                             "device": "cpu", "budget_name": "short", "train": {"common": []},
                             "synth": {"image_size": [160, 64], "frames_per_sequence": 2, "cars_per_frame": [1, 2],
                                       "edit_pairs": 1, "max_edit_operations": 1}})


def _fake_training(monkeypatch, outcome: str) -> None:
    """``sdn3d-train`` replaced: it writes a run (``ok``), writes half a run and fails, or is interrupted."""

    def run(args, env=None):
        run_dir = Path(next(a for a in args if a.startswith("hydra.run.dir=")).split("=", 1)[1])
        run_dir.mkdir(parents=True)
        (run_dir / "train.log").write_text("new")
        if outcome == "interrupt":
            raise KeyboardInterrupt
        if outcome == "ok":
            (run_dir / "summary.json").write_text(json.dumps({"status": "ok", "best_ckpt": str(run_dir / "new")}))
        return subprocess.CompletedProcess(args, 0 if outcome == "ok" else 1)

    monkeypatch.setattr(demo.subprocess, "run", run)


def _earlier_run(runs: Path) -> Path:
    run_dir = runs / "semantic"
    (run_dir / "checkpoints").mkdir(parents=True)
    (run_dir / "checkpoints" / "best.ckpt").write_text("weights")
    (run_dir / "summary.json").write_text(json.dumps({"status": "ok"}))
    return run_dir


@pytest.mark.parametrize("outcome", ["fail", "interrupt"])
def test_a_failed_or_interrupted_retraining_keeps_the_earlier_weights(tmp_path, monkeypatch, outcome):
    runs = tmp_path / "runs"
    run_dir = _earlier_run(runs)
    _fake_training(monkeypatch, outcome)
    with pytest.raises(demo.DemoStageError if outcome == "fail" else KeyboardInterrupt) as caught:
        demo.train_branch("semantic", _cfg(tmp_path), tmp_path / "data", runs)
    assert (run_dir / "checkpoints" / "best.ckpt").read_text() == "weights"
    assert (runs / "semantic.failed" / "train.log").read_text() == "new"
    assert not (runs / ".semantic.previous").exists()
    if outcome == "fail":
        assert f"see {runs / 'semantic.failed'}/train.log; the earlier run is kept in {run_dir}" in str(caught.value)


def test_a_killed_retraining_is_undone_by_the_next_demo(tmp_path, monkeypatch):
    """SIGKILL while training: the earlier run waits in runs/.semantic.previous; the next demo puts it back first
    and replaces it only once its own run finished ok."""
    runs = tmp_path / "runs"
    run_dir = _earlier_run(runs)
    run_dir.rename(runs / ".semantic.previous")
    (run_dir).mkdir()
    (run_dir / "train.log").write_text("killed")
    _fake_training(monkeypatch, "fail")
    with pytest.raises(demo.DemoStageError):
        demo.train_branch("semantic", _cfg(tmp_path), tmp_path / "data", runs)
    assert (run_dir / "checkpoints" / "best.ckpt").read_text() == "weights"
    _fake_training(monkeypatch, "ok")
    summary = demo.train_branch("semantic", _cfg(tmp_path), tmp_path / "data", runs)
    assert summary["status"] == "ok" and (run_dir / "train.log").read_text() == "new"
    assert not (run_dir / "checkpoints").exists() and not (runs / ".semantic.previous").exists()


def test_the_data_are_reused_and_a_users_file_there_is_never_deleted(tmp_path, monkeypatch, capsys):
    cfg = _cfg(tmp_path)
    root = demo.make_data(cfg)
    stamp = (root / "synth_manifest.json").stat().st_mtime_ns
    calls = []
    import sdn3d.data.synth as synth

    monkeypatch.setattr(synth, "generate_dataset", lambda c: calls.append(c))
    assert demo.make_data(cfg) == root and not calls  # the same settings: reused, not regenerated
    assert (root / "synth_manifest.json").stat().st_mtime_ns == stamp
    (root / "notes.txt").write_text("mine")
    (root / "vkitti_1.3.1_rgb" / "0001" / "clone" / "mine.png").write_bytes(b"x")
    other = OmegaConf.merge(cfg, {"seed": 1})
    with pytest.raises(InputError, match=r"holds 2 entries the synthetic generator did not write \('notes.txt', "
                                         r"'vkitti_1.3.1_rgb/0001/clone/mine.png'\)"):
        demo.make_data(other)
    assert not calls and (root / "notes.txt").read_text() == "mine"
    (root / "notes.txt").unlink()
    (root / "vkitti_1.3.1_rgb" / "0001" / "clone" / "mine.png").unlink()
    demo.make_data(other)  # only the generator's files: regenerated with the new settings
    assert len(calls) == 1


def test_the_report_names_what_the_data_hold(tmp_path):
    """The report's data line says what every branch trained on: worlds x variations x frames as the data's manifest
    records them (a weather variation included, issue 40), the vehicles and the seed."""
    cfg = OmegaConf.merge(_cfg(tmp_path), {"synth": {"variations": ["clone", "rain"], "edit_pairs": 0,
                                                       "occluder_pairs": 0}})
    record = {**demo.data_record(demo.make_data(cfg)), "image_size": [160, 64]}
    assert record["frames"] == 4 and record["variations"] == ["clone", "rain"]
    assert demo.data_sentence(record, 0) == ("4 synthetic frames at 160x64 (1 worlds x [clone, rain] x 2 frames, "
                                             "vehicles heldout, seed 0)")
