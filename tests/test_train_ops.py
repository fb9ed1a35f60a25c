"""sdn3d-train end to end: config composition, every branch, TensorBoard, resume after SIGKILL, faults.

Runs on the tiny synthetic dataset (conftest ``tiny_synth``) with the branches' demo experiment
shrunk further by overrides; each run is a few optimiser steps.
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest
import torch
from hydra import compose, initialize_config_dir
from omegaconf import OmegaConf

REPO = Path(__file__).resolve().parents[1]
CONF = str(REPO / "conf")
BRANCHES = ("semantic", "geometric", "textural")

# Per-branch overrides that make a run tiny (on top of experiment=demo).
TINY = {
    "semantic": ["datamodule.batch_size=2", "model.lr=0.001", "model.channels=[4,4,8,8,16,16,16,16]",
                 "model.head_channels=8"],
    "geometric": ["datamodule.batch_size=4", "datamodule.crop_size=32", "datamodule.min_pixels=0"],
    "textural": ["datamodule.batch_size=1"],
}


def _overrides(branch: str, root: Path, run_dir: Path, *extra: str) -> list[str]:
    return [f"branch={branch}", "experiment=demo", f"data.root={root}", "data.image_size=[160,64]",
            f"run_dir={run_dir}", f"summary_file={run_dir.parent / 'summary.jsonl'}", "trainer.max_epochs=1",
            "trainer.limit_val_batches=1", "trainer.limit_test_batches=1", "trainer.log_every_n_steps=1",
            "trainer.enable_progress_bar=false", "~callbacks.progress_bar", *TINY[branch], *extra]


def _compose(overrides: list[str]):
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        return compose("train", overrides=overrides)


def _cli(args: list[str], cwd: Path, timeout: int = 300, env: dict | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(REPO / "tests"), "OMP_NUM_THREADS": "1", **(env or {})}
    return subprocess.run([sys.executable, "-m", "sdn3d.cli.train", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("branch", BRANCHES)
@pytest.mark.parametrize("experiment", ["demo", "paper_vkitti", "paper_cityscapes"])
def test_configs_compose_with_experiments(branch, experiment, tmp_path):
    pytest.importorskip(f"lightning_modules.{branch}")
    before = OmegaConf.to_container(_compose([f"branch={branch}", f"run_dir={tmp_path}"]).trainer, resolve=True)
    cfg = _compose([f"branch={branch}", f"experiment={experiment}", f"run_dir={tmp_path}",
                    "trainer.log_every_n_steps=7"])
    assert cfg.trainer.log_every_n_steps == 7  # the command line beats the experiment
    if experiment == "demo":  # every demo recipe shrinks the budget
        assert OmegaConf.to_container(cfg.trainer, resolve=True) != before
    assert cfg.branch_name == branch and cfg.model._target_.startswith("lightning_modules.")
    assert cfg.datamodule._target_.startswith("datamodules.")
    assert cfg.monitor.startswith("val/") and cfg.monitor_mode in ("min", "max")
    OmegaConf.to_container(cfg.model, resolve=True)  # every interpolation resolves


def test_table2_experiment_sets_the_geometric_budget(tmp_path):
    from hydra.errors import MissingConfigException

    cfg = _compose(["branch=geometric", "experiment=table2", "ablation=no_tau", f"run_dir={tmp_path}",
                    "model.joint_epochs=3"])
    assert cfg.model.pred_epochs == 40 and cfg.model.joint_epochs == 3 and cfg.datamodule.cache_items is True
    assert cfg.trainer.max_epochs == 60 and cfg.model.distance == "log_distance"
    # A multirun hands the overrides over escaped; Hydra parses them as on the command line.
    cfg = _compose(["branch=geometric", "experiment=table2", "trainer.max_time=00\\:00\\:06\\:00",
                    "model.pred_epochs=7", f"run_dir={tmp_path}"])
    assert cfg.trainer.max_time == "00:00:06:00" and cfg.model.pred_epochs == 7
    # only the geometric branch has this budget; the error lists the recipes there are
    with pytest.raises(MissingConfigException, match="recipe/semantic_table2") as err:
        _compose(["branch=semantic", "experiment=table2", f"run_dir={tmp_path}"])
    assert "geometric_table2" in str(err.value)


def test_geometric_ablations_reach_the_model(tmp_path):
    pytest.importorskip("lightning_modules.geometric")
    for name in ("full", "no_reproj", "full_quaternion", "no_tau", "single_cad"):
        cfg = _compose(["branch=geometric", f"ablation={name}", f"run_dir={tmp_path}"])
        resolved = OmegaConf.to_container(cfg, resolve=True)
        assert resolved["ablation"]["name"] == name
        text = json.dumps({"model": resolved["model"], "datamodule": resolved["datamodule"]})
        assert cfg.ablation.rotation in text and cfg.ablation.distance in text


@pytest.mark.parametrize("branch", BRANCHES)
def test_each_branch_trains_tests_and_logs_to_tensorboard(branch, tiny_synth, tmp_path, caplog):
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    from lightning_modules.train import run_training

    pytest.importorskip(f"lightning_modules.{branch}")
    run_dir = tmp_path / "run"
    cfg = _compose(_overrides(branch, tiny_synth, run_dir, "trainer.limit_train_batches=2"))
    with caplog.at_level(logging.INFO, logger="sdn3d.train"):
        summary = run_training(cfg, [])
    # EpochLog: progress in the run's log even without a progress bar
    assert any(r.getMessage().startswith("epoch 1/") and "train/" in r.getMessage()
               for r in caplog.records), [r.getMessage() for r in caplog.records]
    assert summary["status"] == "ok" and summary["global_step"] >= 1
    assert any(k.startswith("test/") for k in summary["metrics"]), summary["metrics"]
    # the tested weights are named: the checkpoint the monitor picked on the validation part
    assert summary["tested_checkpoint"] == "best" and summary["best_ckpt"]
    assert summary["selected_by"].endswith("on the validation part") and cfg.monitor in summary["selected_by"]
    assert (run_dir / "checkpoints" / "last.ckpt").is_file() and (run_dir / "config.yaml").is_file()
    saved = json.loads((run_dir / "summary.json").read_text())
    assert saved["run_dir"] == str(run_dir.resolve())
    lines = (tmp_path / "summary.jsonl").read_text().splitlines()
    assert json.loads(lines[-1])["branch"] == branch

    events = list((run_dir / "tensorboard").rglob("events.out.tfevents.*"))
    assert events, "no TensorBoard event file"
    tags: dict[str, list[str]] = {"scalars": [], "images": [], "tensors": []}
    for event in events:
        acc = EventAccumulator(str(event), size_guidance={"images": 0, "scalars": 0, "tensors": 0})
        acc.Reload()
        for kind in tags:
            tags[kind] += acc.Tags().get(kind, [])
        try:
            tags["tensors"] += list(acc.PluginTagToContent("hparams"))
        except KeyError:  # this event file holds no hparams
            pass
    assert any(t.startswith("train/") for t in tags["scalars"]), tags
    assert any(t.startswith("val/") for t in tags["scalars"]), tags
    assert tags["images"], f"{branch}: no image grid in TensorBoard ({tags})"
    assert "_hparams_/session_start_info" in tags["tensors"], tags


@pytest.mark.slow  # 20 s; test_train_faults' resume test checks the same resume after a clean stop, and
# test_train_checkpointing a SIGKILL while a checkpoint is written
def test_resume_after_sigkill_reaches_the_same_final_step(tiny_synth, tmp_path):
    from lightning_modules.train import run_training

    pytest.importorskip("lightning_modules.semantic")
    run_dir = tmp_path / "run"
    # 4 batches an epoch: the last checkpoint before the kill (step 2) is in the middle of epoch 0
    args = _overrides("semantic", tiny_synth, run_dir, "trainer.max_epochs=-1", "trainer.max_steps=6",
                      "callbacks.step_checkpoint.every_n_train_steps=2", "test_after_fit=false",
                      "trainer.check_val_every_n_epoch=100", "datamodule.batch_size=1")
    killer = ["+callbacks.killer._target_=helpers.train_callbacks.KillAtStep", "+callbacks.killer.env=SDN3D_TEST_KILL",
              "+callbacks.killer.step=3"]
    sys.path.insert(0, str(REPO / "tests"))
    try:  # the same run, never killed
        elsewhere = [f"run_dir={tmp_path / 'straight'}" if a.startswith("run_dir=") else a for a in args]
        straight = run_training(_compose(elsewhere + killer), [])
    finally:
        sys.path.remove(str(REPO / "tests"))
    args = [a for a in args if not a.startswith("run_dir=")] + [f"hydra.run.dir={run_dir}"]
    killed = _cli(args + killer, cwd=tmp_path, env={"SDN3D_TEST_KILL": "1"})
    assert killed.returncode == -9, killed.stderr[-2000:]
    state = torch.load(run_dir / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=False)
    assert state["global_step"] == 2  # the last good checkpoint: step 2 (step 3 died before its save)
    # The saved config names the test's killer callback: a resumed config is trusted only for sdn3d's, Lightning's
    # and torch's classes unless the command line says otherwise.
    resumed = _cli([f"resume={run_dir}", "resume_allow_targets=[helpers.]"], cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stdout[-3000:] + resumed.stderr[-3000:]
    summary = json.loads((run_dir / "summary.json").read_text())
    assert summary["global_step"] == 6 and summary["status"] == "ok"
    final = torch.load(run_dir / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=True)
    assert final["global_step"] == 6 and "optimizer_states" in final and final["optimizer_states"]
    # ...and the same weights as the run that was never killed: the resumed run went on with the data order
    # (the rest of epoch 0, then epoch 1) and the random state of the killed one
    reference = torch.load(straight["last_ckpt"], map_location="cpu", weights_only=True)["state_dict"]
    assert not [k for k, v in final["state_dict"].items() if not torch.equal(v, reference[k])]
    assert len(list((run_dir / "tensorboard").glob("events.out.tfevents.*"))) >= 1
    assert not list((tmp_path / "outputs").rglob("config.yaml"))  # nothing written outside the resumed run


def test_nonfinite_loss_stops_with_message_or_skips(tiny_synth, tmp_path):
    from lightning_modules.train import run_training
    from sdn3d.training.errors import TrainingError

    pytest.importorskip("lightning_modules.semantic")
    poison = ["+callbacks.poison._target_=helpers.train_callbacks.PoisonBatchAtStep", "+callbacks.poison.step=1"]
    sys.path.insert(0, str(REPO / "tests"))
    try:
        run_dir = tmp_path / "stop"
        cfg = _compose(_overrides("semantic", tiny_synth, run_dir, "trainer.max_steps=3",
                                  "callbacks.step_checkpoint.every_n_train_steps=1", *poison))
        with pytest.raises(TrainingError, match="non-finite training loss"):
            run_training(cfg, [])
        good = torch.load(run_dir / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=False)
        assert good["global_step"] == 1
        assert all(torch.isfinite(v).all() for v in good["state_dict"].values() if v.is_floating_point())
        assert json.loads((run_dir / "summary.json").read_text())["status"] == "failed"

        run_dir = tmp_path / "skip"
        cfg = _compose(_overrides("semantic", tiny_synth, run_dir, "trainer.max_steps=2", "fault.nonfinite=skip",
                                  *poison))
        summary = run_training(cfg, [])
        assert summary["status"] == "ok" and summary["skipped_batches"] == 1 and summary["global_step"] == 2
    finally:
        sys.path.remove(str(REPO / "tests"))


def test_corrupt_sample_fails_naming_the_file_or_is_skipped(tiny_synth, tmp_path):
    import shutil

    from lightning_modules.train import run_training
    from sdn3d.data.errors import DataFormatError

    pytest.importorskip("lightning_modules.semantic")
    root = tmp_path / "data"
    shutil.copytree(tiny_synth, root)
    # Frame 2: found unreadable while indexing (its header), named under fail, left out under skip.
    bad = sorted((root / "vkitti_1.3.1_rgb").rglob("00002.png"))[0]
    bad.write_bytes(b"\x89PNG\r\n\x1a\n truncated")
    cfg = _compose(_overrides("semantic", root, tmp_path / "fail", "trainer.max_steps=2"))
    with pytest.raises(DataFormatError, match="00002.png"):
        run_training(cfg, [])
    failed = json.loads((tmp_path / "fail" / "summary.json").read_text())
    assert failed["status"] == "failed" and failed["error_file"] == str(bad) and "00002.png" in failed["error"]
    # 1 of the 4 training frames is more than the default fault.max_skipped_fraction (0.1) allows
    cfg = _compose(_overrides("semantic", root, tmp_path / "skip", "trainer.max_steps=2",
                              "fault.corrupt_sample=skip", "fault.max_skipped_fraction=0.5"))
    summary = run_training(cfg, [])
    assert summary["status"] == "ok" and summary["skipped_samples"] == 1 and summary["skipped_files"] == [str(bad)]
    assert summary["skipped_fraction"] == 0.25


def test_unwritable_output_dir_is_a_clear_error(tiny_synth, tmp_path):
    blocker = tmp_path / "not_a_dir"
    blocker.write_text("x")
    proc = _cli(_overrides("semantic", tiny_synth, blocker / "run") + [f"hydra.run.dir={tmp_path / 'h'}"],
                cwd=tmp_path)
    assert proc.returncode == 2  # a user's mistake: one line, no traceback
    assert "sdn3d-train: error: output directory" in proc.stderr and "is not writable" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_multirun_ablations_write_one_summary(tiny_synth, tmp_path):
    pytest.importorskip("lightning_modules.geometric")
    summary = tmp_path / "summary.jsonl"
    args = [a for a in _overrides("geometric", tiny_synth, tmp_path / "unused", "trainer.max_steps=1")
            if not a.startswith(("run_dir=", "summary_file="))]
    proc = _cli(["-m", *args, "ablation=full,no_tau", f"summary_file={summary}",
                 f"hydra.sweep.dir={tmp_path / 'sweep'}"], cwd=tmp_path, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    records = [json.loads(line) for line in summary.read_text().splitlines()]
    assert sorted(r["ablation"] for r in records) == ["full", "no_tau"]
    assert all(Path(r["run_dir"]).parent == (tmp_path / "sweep").resolve() for r in records)
    assert all("test/orientation_similarity" in r["metrics"] for r in records)


@pytest.mark.parametrize("branch", [
    "semantic",
    # Spawning two processes per branch costs ~1 min on 2 cores: the other branches run with -m slow.
    pytest.param("geometric", marks=pytest.mark.slow),
    pytest.param("textural", marks=pytest.mark.slow),
])
def test_ddp_two_cpu_processes_agree_on_weights(branch, tiny_synth, tmp_path):
    pytest.importorskip(f"lightning_modules.{branch}")
    out = tmp_path / "weights"
    args = [a for a in _overrides(branch, tiny_synth, tmp_path / "run", "trainer=ddp_cpu", "trainer.max_steps=2",
                                  "trainer.max_epochs=-1",
                                  "test_after_fit=false", "logger=none", "callbacks=none")
            if not a.startswith(("run_dir=", "~callbacks"))]
    args += [f"hydra.run.dir={tmp_path / 'run'}", "+callbacks.save._target_=helpers.train_callbacks.SaveRankWeights",
             f"+callbacks.save.dirpath={out}"]
    # TMPDIR: Lightning's ddp_spawn leaves an empty tempfile.mkdtemp() directory behind (rank 0's weights went there)
    proc = _cli(args, cwd=tmp_path, timeout=600, env={"TMPDIR": str(tmp_path)})
    assert proc.returncode == 0, proc.stderr[-3000:]
    r0 = torch.load(out / "rank0.pt", weights_only=True)
    r1 = torch.load(out / "rank1.pt", weights_only=True)
    assert r0["step"] == r1["step"] == 2
    for key, value in r0["state"].items():
        assert torch.allclose(value.float(), r1["state"][key].float(), atol=1e-6), key
    # ...and training changed them (the ranks did not just agree on the initialisation).
    assert any(not torch.equal(v, r0["initial"][k]) for k, v in r0["state"].items() if v.is_floating_point())
