"""sdn3d-train under faults (issue 20): crafted checkpoints and configs, diverged runs, corrupt data, full
disks, an unwritable summary file, and a resume that must train exactly like a straight run.

Each run is a few optimiser steps on the tiny synthetic dataset (conftest ``tiny_synth``), broken with
the helpers of ``tests/faults/data.py``.
"""

from __future__ import annotations

import errno
import json
import shutil
import sys
from pathlib import Path

import lightning as L
import pytest
import torch
from faults.checkpoints import RANDOM_SEEDS, random_bytes
from faults.data import bad_motgt_row, truncated_png, unknown_colour_png, vkitti1_frame_files
from hydra import compose, initialize_config_dir
from lightning.fabric.plugins.io.torch_io import TorchCheckpointIO
from omegaconf import OmegaConf

from lightning_modules.checkpointing import AtomicCheckpointIO, CheckpointLoadError, CheckpointWriteError
from lightning_modules.train import run_training
from sdn3d.data.errors import DataFormatError
from sdn3d.training.errors import RunFailedError, TrainingError
from sdn3d.training.resume import resolve_resume

REPO = Path(__file__).resolve().parents[1]
TINY = {
    "semantic": ["datamodule.batch_size=2", "model.lr=0.001", "model.channels=[4,4,8,8,16,16,16,16]",
                 "model.head_channels=8"],
    "geometric": ["datamodule.batch_size=4", "datamodule.crop_size=32", "datamodule.min_pixels=0"],
}


@pytest.fixture(autouse=True)
def _tests_importable():
    """Callbacks of this module are named by ``_target_`` (``test_train_faults.X``)."""
    sys.path.insert(0, str(REPO / "tests"))
    yield
    sys.path.remove(str(REPO / "tests"))


def _cfg(branch: str, root: Path, run_dir: Path, *extra: str):
    overrides = [f"branch={branch}", "experiment=demo", f"data.root={root}", "data.image_size=[160,64]",
                 f"run_dir={run_dir}", f"summary_file={run_dir.parent / 'summary.jsonl'}", "trainer.max_epochs=1",
                 "trainer.limit_val_batches=1", "trainer.limit_test_batches=1", "trainer.log_every_n_steps=1",
                 "trainer.enable_progress_bar=false", "~callbacks.progress_bar", "logger=none",
                 "test_after_fit=false", *TINY[branch], *extra]
    with initialize_config_dir(config_dir=str(REPO / "conf"), version_base="1.3"):
        return compose("train", overrides=overrides)


def _summaries(run_dir: Path) -> tuple[dict, dict]:
    """The run's summary.json and its summary_file line (the last one)."""
    line = (run_dir.parent / "summary.jsonl").read_text().splitlines()[-1]
    return json.loads((run_dir / "summary.json").read_text()), json.loads(line)


def _copy(tiny_synth: Path, tmp_path: Path) -> Path:
    root = tmp_path / "data"
    shutil.copytree(tiny_synth, root)
    return root


class _OpensFileWhenUnpickled:
    """Unpickling this calls ``open(path, "w")``: a stand-in for any code a crafted checkpoint could run."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def __reduce__(self):
        return (open, (str(self.path), "w"))


class PoisonEveryBatch(L.Callback):
    """Fill every training batch's float tensors with NaN: every loss is non-finite (a diverged run)."""

    def on_train_batch_start(self, trainer, pl_module, batch, batch_idx) -> None:
        for value in batch.values():
            if isinstance(value, torch.Tensor) and value.is_floating_point():
                value.fill_(float("nan"))


class InfRunningVarAtStep(L.Callback):
    """After optimiser step ``step``, set a BatchNorm's running variance to inf (the loss stays finite)."""

    def __init__(self, step: int) -> None:
        self.step = int(step)

    def on_train_batch_end(self, trainer, pl_module, outputs, batch, batch_idx) -> None:
        if trainer.global_step >= self.step:
            bn = next(m for m in pl_module.modules() if isinstance(m, torch.nn.BatchNorm2d))
            bn.running_var.fill_(float("inf"))


class StopAfterEpoch(L.Callback):
    """End the run after epoch ``epoch`` (0-based), as if it had been stopped there."""

    def __init__(self, epoch: int) -> None:
        self.epoch = int(epoch)

    def on_train_epoch_end(self, trainer, pl_module) -> None:
        if trainer.current_epoch >= self.epoch:
            trainer.should_stop = True


# -- 3: nothing a checkpoint or a resumed config names is run -----------------------------------------------------
def test_checkpoints_load_weights_only_even_when_torch_is_told_otherwise(tmp_path, monkeypatch):
    marker, crafted = tmp_path / "ran", tmp_path / "crafted.ckpt"
    torch.save({"state_dict": {}, "payload": _OpensFileWhenUnpickled(marker)}, crafted)
    monkeypatch.setenv("TORCH_FORCE_NO_WEIGHTS_ONLY_LOAD", "1")
    TorchCheckpointIO().load_checkpoint(crafted)  # the probe: Lightning's own loader runs the payload
    assert marker.exists()
    marker.unlink()
    with pytest.raises(CheckpointLoadError, match=r"crafted\.ckpt: refused"):
        AtomicCheckpointIO().load_checkpoint(crafted, weights_only=False)
    assert not marker.exists()


@pytest.mark.parametrize("seed", RANDOM_SEEDS)
def test_a_damaged_checkpoint_is_a_load_error_whatever_torch_raises(tmp_path, seed):
    """Random bytes make torch's loader raise IndexError, KeyError, UnicodeDecodeError, ... (see faults.checkpoints)."""
    path = random_bytes(tmp_path / "damaged.ckpt", seed)
    with pytest.raises(CheckpointLoadError, match=r"damaged\.ckpt: (not a readable checkpoint|refused)"):
        AtomicCheckpointIO().load_checkpoint(path)


def test_fit_from_a_crafted_checkpoint_is_refused_and_recorded(tiny_synth, tmp_path, monkeypatch):
    marker, crafted = tmp_path / "ran", tmp_path / "crafted.ckpt"
    torch.save({"state_dict": {}, "payload": _OpensFileWhenUnpickled(marker)}, crafted)
    monkeypatch.setenv("TORCH_FORCE_NO_WEIGHTS_ONLY_LOAD", "1")
    run_dir = tmp_path / "run"
    # checked before the run starts (issue 32): refused, its payload never run, nothing written
    with pytest.raises(TrainingError, match=r"ckpt_path: could not read checkpoint .*crafted\.ckpt.*weights-only "
                                            r"loading refused it"):
        run_training(_cfg("semantic", tiny_synth, run_dir, f"ckpt_path={crafted}"), [])
    assert not marker.exists()
    assert not run_dir.exists() and not (tmp_path / "summary.jsonl").exists()


def test_a_resumed_config_may_only_instantiate_trusted_classes(tmp_path):
    run = tmp_path / "run"
    (run / "checkpoints").mkdir(parents=True)
    (run / "checkpoints" / "last.ckpt").write_bytes(b"x")
    source, copied = tmp_path / "secret.txt", tmp_path / "copied.txt"
    source.write_text("secret")
    config = {"seed": 0, "callbacks": {"ok": {"_target_": "lightning.pytorch.callbacks.ModelCheckpoint"},
                                       "evil": {"_target_": "shutil.copyfile", "src": str(source),
                                                "dst": str(copied)}}}
    (run / "config.yaml").write_text(OmegaConf.to_yaml(config))
    message = r"config\.yaml: callbacks\.evil\._target_ = 'shutil\.copyfile' is not allowed"
    with pytest.raises(TrainingError, match=message):
        run_training(OmegaConf.create({"resume": str(run)}), [f"resume={run}"])
    assert not copied.exists()
    # trusting a prefix on the command line does not make a function a class
    with pytest.raises(TrainingError, match="is not a class"):
        resolve_resume(OmegaConf.create({"resume": str(run), "resume_allow_targets": ["shutil."]}))
    config["callbacks"]["evil"] = {"_target_": "sdn3d.io.write_text_atomic", "path": str(copied), "text": "x"}
    (run / "config.yaml").write_text(OmegaConf.to_yaml(config))
    with pytest.raises(TrainingError, match=r"callbacks\.evil\._target_ = 'sdn3d\.io\.write_text_atomic' is not a cl"):
        resolve_resume(OmegaConf.create({"resume": str(run)}))
    del config["callbacks"]["evil"]
    (run / "config.yaml").write_text(OmegaConf.to_yaml(config))
    assert resolve_resume(OmegaConf.create({"resume": str(run)})).callbacks.ok._target_.startswith("lightning.")
    assert not copied.exists()


def test_resume_trains_exactly_like_a_straight_run(tiny_synth, tmp_path):
    """4 epochs straight == 2 epochs, stopped, resumed for 2 more: model, optimiser, schedules, data order and
    random state all carry over (geometric: two stages, a step schedule, REINFORCE sampling)."""
    common = ["trainer.max_epochs=4", "model.pred_epochs=2", "model.joint_epochs=2", "model.num_samples=2",
              "model.log_images=0"]
    run_training(_cfg("geometric", tiny_synth, tmp_path / "straight", *common), [])
    split = tmp_path / "split"
    stop = ["+callbacks.stop._target_=test_train_faults.StopAfterEpoch", "+callbacks.stop.epoch=1"]
    half = run_training(_cfg("geometric", tiny_synth, split, *common, *stop), [])["global_step"]
    run_training(_cfg("geometric", tiny_synth, split, *common, f"ckpt_path={split / 'checkpoints' / 'last.ckpt'}",
                 "overwrite=true"), [])  # a new run from the checkpoint, into the same directory
    straight = torch.load(tmp_path / "straight" / "checkpoints" / "last.ckpt", weights_only=True)
    resumed = torch.load(split / "checkpoints" / "last.ckpt", weights_only=True)
    assert straight["global_step"] == resumed["global_step"] == 2 * half > 0
    differ = [k for k, v in straight["state_dict"].items() if not torch.equal(v, resumed["state_dict"][k])]
    assert not differ, differ[:5]


# -- 4: a diverged run stops, and its weights are never checkpointed ----------------------------------------------
def test_skip_policy_gives_up_on_a_diverged_run(tiny_synth, tmp_path):
    run_dir = tmp_path / "run"
    cfg = _cfg("semantic", tiny_synth, run_dir, "trainer.max_epochs=3", "fault.nonfinite=skip",
               "fault.max_skipped_batches=2", "+callbacks.poison._target_=test_train_faults.PoisonEveryBatch")
    with pytest.raises(RunFailedError, match="3 consecutive batches, more than fault.max_skipped_batches=2"):
        run_training(cfg, [])
    summary, line = _summaries(run_dir)
    assert summary["status"] == line["status"] == "failed" and summary["skipped_batches"] == 3
    assert "diverged" in summary["error"]


def test_nonfinite_weights_are_never_written(tmp_path, tiny_synth):
    io, path = AtomicCheckpointIO(), tmp_path / "last.ckpt"
    io.save_checkpoint({"step": 1, "state_dict": {"net.w": torch.ones(3)}}, path)
    bad = {"net.w": torch.tensor([1.0, float("nan"), 2.0]), "net.b": torch.ones(2), "n": torch.tensor(3)}
    with pytest.raises(RuntimeError, match=r"NaN or infinity \(net\.w\); the previous checkpoint"):
        io.save_checkpoint({"step": 2, "state_dict": bad}, path)
    assert io.load_checkpoint(path)["step"] == 1
    # in a run: BatchNorm statistics gone to inf (the loss stays finite) -> failed, the last good checkpoint kept
    run_dir = tmp_path / "run"
    inf = ["+callbacks.inf._target_=test_train_faults.InfRunningVarAtStep", "+callbacks.inf.step=2",
           "callbacks.step_checkpoint.every_n_train_steps=1"]
    cfg = _cfg("semantic", tiny_synth, run_dir, "trainer.max_steps=3", *inf)
    with pytest.raises(RunFailedError, match="NaN or infinity"):
        run_training(cfg, [])
    good = torch.load(run_dir / "checkpoints" / "last.ckpt", weights_only=True)
    assert good["global_step"] == 1
    assert all(torch.isfinite(v).all() for v in good["state_dict"].values() if v.is_floating_point())
    assert _summaries(run_dir)[0]["status"] == "failed"


# -- 5: every run that starts records how it ended ----------------------------------------------------------------
def test_corrupt_sample_is_recorded_or_counted(tiny_synth, tmp_path):
    root = _copy(tiny_synth, tmp_path)
    bad = truncated_png(vkitti1_frame_files(root)[2])  # its header reads: found while training, not indexing
    run_dir = tmp_path / "fail"
    with pytest.raises(DataFormatError, match="00002.png"):
        run_training(_cfg("semantic", root, run_dir, "trainer.max_steps=2"), [])
    summary, line = _summaries(run_dir)
    assert summary["status"] == line["status"] == "failed" and line["run_dir"] == str(run_dir.resolve())
    assert summary["error_file"] == str(bad) and "00002.png" in summary["error"] and "\n" not in summary["error"]
    run_dir = tmp_path / "skip"
    summary = run_training(_cfg("semantic", root, run_dir, "trainer.max_epochs=1", "fault.corrupt_sample=skip",
                                "fault.max_skipped_fraction=0.5"), [])
    assert summary["status"] == "ok" and summary["skipped_samples"] == 1 and summary["skipped_files"] == [str(bad)]
    # ...but not past fault.max_skipped_fraction (1 of 4 training frames > 0.1)
    with pytest.raises(DataFormatError, match="more than fault.max_skipped_fraction=0.1"):
        run_training(_cfg("semantic", root, tmp_path / "bound", "fault.corrupt_sample=skip"), [])
    assert _summaries(tmp_path / "bound")[0]["status"] == "failed"


def test_data_format_error_and_full_disk_are_recorded(tiny_synth, tmp_path, monkeypatch):
    root = _copy(tiny_synth, tmp_path)
    motgt = bad_motgt_row(next((root / "vkitti_1.3.1_motgt").glob("*.txt")), row=1)
    with pytest.raises(DataFormatError, match=r":3: column 11 \('w3d'\)"):
        run_training(_cfg("semantic", root, tmp_path / "format"), [])
    summary, _ = _summaries(tmp_path / "format")
    assert summary["status"] == "failed" and summary["error_file"] == str(motgt)

    def disk_full(path, writer):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr("lightning_modules.checkpointing.atomic_write", disk_full)
    run_dir = tmp_path / "disk"
    with pytest.raises(CheckpointWriteError, match="the disk is full"):
        run_training(_cfg("semantic", tiny_synth, run_dir, "trainer.max_steps=1"), [])
    summary, line = _summaries(run_dir)
    assert summary["status"] == line["status"] == "failed" and summary["error"].startswith("CheckpointWriteError")
    assert summary["error_file"].startswith(str(run_dir / "checkpoints")) and summary["last_ckpt"] is None


def test_cli_user_error_is_one_line_exit_2_and_recorded(tiny_synth, tmp_path):
    import os
    import subprocess

    root = _copy(tiny_synth, tmp_path)
    bad = truncated_png(vkitti1_frame_files(root)[1])
    run_dir = tmp_path / "run"
    args = [f"hydra.run.dir={run_dir}", "branch=semantic", "experiment=demo", f"data.root={root}",
            "data.image_size=[160,64]", f"summary_file={tmp_path / 'summary.jsonl'}", "trainer.max_steps=2",
            "trainer.enable_progress_bar=false", "~callbacks.progress_bar", "logger=none", *TINY["semantic"]]
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-m", "sdn3d.cli.train", *args], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr and proc.stderr.strip().splitlines()[-1].startswith("sdn3d-train: error: ")
    line = json.loads((tmp_path / "summary.jsonl").read_text().splitlines()[-1])
    assert line["status"] == "failed" and line["error_file"] == str(bad)


def test_summary_file_is_checked_before_training(tiny_synth, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    run_dir = tmp_path / "run"
    cfg = _cfg("semantic", tiny_synth, run_dir, f"summary_file={blocker / 'summary.jsonl'}")
    with pytest.raises(TrainingError, match="summary_file .* is not writable"):
        run_training(cfg, [])
    assert not (run_dir / "checkpoints").exists()  # nothing trained


# -- 7: index-time reads follow fault.corrupt_sample ---------------------------------------------------------------
def test_bad_scenegt_found_while_indexing_is_skipped_and_counted(tiny_synth, tmp_path):
    root = _copy(tiny_synth, tmp_path)
    frame = vkitti1_frame_files(root)[1]
    scenegt = unknown_colour_png(root / "vkitti_1.3.1_scenegt" / frame.relative_to(root / "vkitti_1.3.1_rgb"))
    with pytest.raises(DataFormatError, match=str(scenegt)):  # the geometric index reads every instance map
        run_training(_cfg("geometric", root, tmp_path / "fail"), [])
    summary = run_training(_cfg("geometric", root, tmp_path / "skip", "trainer.max_steps=2",
                                "fault.corrupt_sample=skip", "fault.max_skipped_fraction=0.5"), [])
    assert summary["status"] == "ok" and summary["skipped_samples"] == 1
    assert summary["skipped_files"] == [str(scenegt)] and summary["skipped_fraction"] == 0.25
