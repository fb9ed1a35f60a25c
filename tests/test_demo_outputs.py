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


def test_the_geometric_branch_trains_on_its_own_set_and_the_report_says_so(tmp_path):
    """Issue 40: ``geometric_synth`` gives the geometric branch its own synthetic set (synth's fields with its own in
    their place) in ``geometric_data_dir``; only that branch trains there, the report's data line and its branch
    line say so; null: none is made and every branch trains on the demo's data."""
    own = {"worlds": ["0101", "0102"], "variations": ["clone", "rain"], "frames_per_sequence": 2, "edit_pairs": 0,
           "occluder_pairs": 0}
    cfg = OmegaConf.merge(_cfg(tmp_path), {"geometric_data_dir": str(tmp_path / "geo"), "geometric_synth": own})
    assert demo.geometric_synth(cfg)["image_size"] == [160, 64]  # synth's, where the set gives none
    root = demo.make_geometric_data(cfg)
    assert root == tmp_path / "geo"
    manifest = json.loads((root / "synth_manifest.json").read_text())["config"]
    assert manifest["worlds"] == ["0101", "0102"] and manifest["variations"] == ["clone", "rain"]
    assert sorted(p.name for p in (root / "vkitti_1.3.1_rgb").iterdir()) == ["0101", "0102"]
    assert demo.branch_data_root("geometric", cfg, tmp_path / "data") == root
    assert all(demo.branch_data_root(b, cfg, tmp_path / "data") == tmp_path / "data" for b in ("semantic", "textural"))
    assert f"data.root={root.resolve()}" in demo._train_command("geometric", cfg, tmp_path / "data", tmp_path / "runs")
    record = {**demo.data_record(root), "generate_s": 1.0}
    assert record["frames"] == 8
    info = {"seed": 0, "training": {"geometric": {"global_step": 40, "demo_wall_s": 9.0, "metrics": {}}},
            "data": {"geometric": record}}
    [line] = demo.branch_lines(info["training"], None, info["data"])
    assert "on its own synthetic set, 2 worlds x 2 frames, its test part" in line
    assert demo._geometric_data_line(info).startswith(
        "- The geometric branch trained and was tested on its own synthetic set: 8 synthetic frames at 160x64 "
        "(2 worlds x [clone, rain] x 2 frames, vehicles heldout, seed 0)")
    none = OmegaConf.merge(cfg, {"geometric_synth": None})
    assert demo.make_geometric_data(none) is None and demo._geometric_data_line({"data": {}}) == ""
    assert demo.branch_data_root("geometric", none, tmp_path / "data") == tmp_path / "data"
