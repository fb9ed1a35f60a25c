"""Atomic checkpoints, corrupt-sample policy and resume resolution (no training here)."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import torch
from omegaconf import OmegaConf
from torch.utils.data import Dataset

from datamodules.guard import CorruptSampleError, SampleGuard
from lightning_modules._base import image_grid
from lightning_modules.checkpointing import AtomicCheckpointIO, CheckpointWriteError
from sdn3d.data.errors import DataFormatError
from sdn3d.training.errors import TrainingError
from sdn3d.training.resume import resolve_resume
from sdn3d.training.rundir import check_writable

REPO = Path(__file__).resolve().parents[1]


def test_atomic_checkpoint_roundtrip_and_failed_write_keeps_previous(tmp_path, monkeypatch):
    io = AtomicCheckpointIO()
    path = tmp_path / "ckpt" / "last.ckpt"
    io.save_checkpoint({"step": 1, "w": torch.arange(4.0)}, path)
    assert io.load_checkpoint(path, weights_only=True)["step"] == 1

    def disk_full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", disk_full)
    with pytest.raises(CheckpointWriteError, match="disk is full"):
        io.save_checkpoint({"step": 2, "w": torch.zeros(4)}, path)
    monkeypatch.undo()
    assert io.load_checkpoint(path, weights_only=True)["step"] == 1
    assert sorted(p.name for p in path.parent.iterdir()) == ["last.ckpt"]  # no temp file left behind


def test_sigkill_while_writing_checkpoint_keeps_previous(tmp_path):
    """A process killed in the middle of writing last.ckpt leaves the previous one loadable."""
    path = tmp_path / "last.ckpt"
    script = textwrap.dedent(f"""
        import os, signal, torch
        from lightning_modules.checkpointing import AtomicCheckpointIO
        io = AtomicCheckpointIO()
        io.save_checkpoint({{"step": 1, "w": torch.ones(1000)}}, {str(path)!r})
        real_fsync = os.fsync
        def die(fd):  # the bytes are in the temp file, the rename has not happened: crash now
            os.kill(os.getpid(), signal.SIGKILL)
        os.fsync = die
        io.save_checkpoint({{"step": 2, "w": torch.zeros(1000)}}, {str(path)!r})
    """)
    proc = subprocess.run([sys.executable, "-c", script], cwd=REPO, capture_output=True, timeout=120)
    assert proc.returncode == -signal.SIGKILL
    state = torch.load(path, weights_only=True)
    assert state["step"] == 1 and torch.equal(state["w"], torch.ones(1000))


class _Flaky(Dataset):
    def __init__(self, bad: set[int]) -> None:
        self.bad = bad

    def __len__(self) -> int:
        return 5

    def __getitem__(self, i: int) -> int:
        if i in self.bad:
            raise DataFormatError(f"/data/frame_{i:05d}.png: unreadable image (truncated)")
        return i


def test_sample_guard_fail_names_file_and_skip_serves_next():
    with pytest.raises(CorruptSampleError, match=r"frame_00002\.png"):
        SampleGuard(_Flaky({2}), "fail")[2]
    guard = SampleGuard(_Flaky({2}), "skip")
    assert [guard[i] for i in range(5)] == [0, 1, 3, 3, 4]
    assert guard.skipped == {2}
    with pytest.raises(CorruptSampleError, match="dataset looks broken"):
        SampleGuard(_Flaky(set(range(5))), "skip", max_skips=3)[0]
    with pytest.raises(ValueError, match="corrupt_sample"):
        SampleGuard(_Flaky(set()), "ignore")


def test_resolve_resume_errors_and_overrides(tmp_path):
    run = tmp_path / "run"
    with pytest.raises(TrainingError, match="no config.yaml"):
        resolve_resume(OmegaConf.create({"resume": str(run)}))
    run.mkdir()
    (run / "config.yaml").write_text("seed: 3\ntrainer:\n  max_epochs: 2\nrun_dir: /elsewhere\n")
    with pytest.raises(TrainingError, match="no checkpoints/last.ckpt"):
        resolve_resume(OmegaConf.create({"resume": str(run)}))
    (run / "checkpoints").mkdir()
    (run / "checkpoints" / "last.ckpt").write_bytes(b"x")
    cfg = resolve_resume(OmegaConf.create({"resume": str(run)}), ["resume=" + str(run), "trainer.max_epochs=5"])
    assert cfg.trainer.max_epochs == 5 and cfg.seed == 3 and cfg.run_dir == str(run)
    with pytest.raises(TrainingError, match="'branch=textural' with resume=.*group's choice.*can not change"):
        resolve_resume(OmegaConf.create({"resume": str(run)}), ["resume=" + str(run), "branch=textural"])
    assert cfg.ckpt_path == str(run / "checkpoints" / "last.ckpt")


def test_check_writable(tmp_path):
    check_writable(tmp_path / "a" / "b")
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(TrainingError, match="is not writable"):
        check_writable(blocker / "run")


def test_image_grid_layout():
    a = torch.zeros(2, 3, 4, 5)
    b = torch.ones(2, 1, 4, 5)
    grid = image_grid([a, b], pad=1)
    assert grid.shape == (3, 2 * 5 + 1, 2 * 6 + 1)
    assert grid[:, 1:5, 1:6].max() == 0 and grid[:, 1:5, 7:12].min() == 1
    with pytest.raises(ValueError, match="image_grid"):
        image_grid([a, torch.zeros(3, 3, 4, 5)])


def test_stale_checkpoint_temp_files_are_removed_at_start_and_resume(tmp_path):
    from sdn3d.training.rundir import prepare_run_dir

    run = tmp_path / "run"
    checkpoints = run / "checkpoints"
    checkpoints.mkdir(parents=True)
    for resume in (None, str(run)):
        stale = [checkpoints / ".last.ckpt.k2j3h4x_.tmp", checkpoints / ".best-epoch003.ckpt.abc12.tmp",
                 run / ".summary.json.q1w2.tmp"]  # what a SIGKILL during an atomic write leaves behind
        keep = [checkpoints / "last.ckpt", checkpoints / ".notes.tmp", run / "train.log"]
        for path in stale + keep:
            path.write_bytes(b"x")
        prepare_run_dir(OmegaConf.create({"run_dir": str(run), "resume": resume, "summary_file": None}))
        assert not [p for p in stale if p.exists()] and all(p.exists() for p in keep)


class _FlakyDicts(_Flaky):
    def __getitem__(self, i: int) -> dict:
        return {"x": torch.tensor(float(super().__getitem__(i)))}


def test_skip_policy_tags_dict_samples_so_the_training_process_counts_them():
    from torch.utils.data import DataLoader

    from datamodules import SemanticDataModule
    from datamodules.guard import SKIP_KEY

    guard = SampleGuard(_FlakyDicts({2}), "skip")
    batch = next(iter(DataLoader(guard, batch_size=5)))  # what a loader worker hands back
    assert batch["x"].tolist() == [0, 1, 3, 3, 4]
    assert batch[SKIP_KEY] == ["", "", "2\t/data/frame_00002.png\t/data/frame_00002.png: unreadable image (truncated)",
                               "", ""]
    dm = SemanticDataModule({"kind": "vkitti1", "root": "/data"}, corrupt_sample="skip", max_skipped_fraction=0.5)
    dm.datasets["train"] = guard
    guard.skipped.clear()
    guard.messages.clear()  # as in the main process when a worker did the reading
    out = dm.on_before_batch_transfer(batch, 0)
    assert SKIP_KEY not in out and out["x"] is batch["x"]
    assert dm.skip_summary() == {"skipped_samples": 1, "skipped_fraction": 0.2,
                                 "skipped_files": ["/data/frame_00002.png"]}
    assert SampleGuard(_FlakyDicts({2}), "fail")[0] == {"x": torch.tensor(0.0)}  # fail: samples unchanged
