"""Issue 32, a resume that fails leaves the run as it was.

Before: ``resume=`` with a smaller ``trainer.max_epochs`` than trained, or a run whose ``last.ckpt`` is an inference
export, ended in a traceback (``MisconfigurationException``, ``KeyError: 'pytorch-lightning_version'``) after
rewriting the finished run's ``summary.json`` as failed with empty metrics (``sdn3d-edit run=`` then refused the
run); ``ckpt_path=<inference.pt>`` gave the same ``KeyError``; resuming a finished run re-tested it and rewrote its
summary (experiment null, overrides replaced); overrides without a dot (``threads=1``, ``summary_file=``) and
group choices were dropped without a word. Now: those mistakes stop before anything is written (a
``TrainingError``: exit 2), a finished run resumed without a larger budget is left alone, a failed resume records
itself in ``<run>/summary_log.jsonl`` and ``summary_file`` only, and every override is applied or refused.

One tiny semantic run (2 epochs of 1 batch on the 160x64 synthetic data) is trained per module; each test copies it.
"""

from __future__ import annotations

import hashlib
import json
import logging
import shutil
from pathlib import Path

import pytest
import torch
from helpers.tiny_training import TINY_SEMANTIC, compose_train, resume, train_tiny
from omegaconf import OmegaConf

from lightning_modules.train import run_training
from sdn3d.errors import UserInputError
from sdn3d.runs import find_run_checkpoints
from sdn3d.training.errors import TrainingError
from sdn3d.training.resume import resolve_resume

TRAIN = [*TINY_SEMANTIC, "test_after_fit=false"]


@pytest.fixture(scope="module")
def trained(tiny_synth, tmp_path_factory) -> Path:
    """A finished run (status ok, 2 of 2 epochs) with its inference export."""
    run_dir = tmp_path_factory.mktemp("trained") / "run"
    assert train_tiny(tiny_synth, run_dir, "test_after_fit=false")["status"] == "ok"
    assert (run_dir / "checkpoints" / "inference.pt").is_file()
    return run_dir


def _copy(trained: Path, tmp_path: Path) -> Path:
    run = tmp_path / "run"
    shutil.copytree(trained, run)
    return run


def _files(run: Path) -> dict[str, str]:
    """Every file of the run directory and the SHA-256 of its bytes."""
    return {str(p.relative_to(run)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(run.rglob("*")) if p.is_file()}


@pytest.mark.parametrize("budget", ["trainer.max_epochs=1", "trainer.max_steps=1"])
def test_a_smaller_budget_than_trained_is_refused_before_anything_is_written(trained, tmp_path, budget):
    run = _copy(trained, tmp_path)
    before = _files(run)
    with pytest.raises(TrainingError, match=rf"last\.ckpt' has trained 2 epoch\(s\), 2 optimiser step\(s\): "
                                            rf"{budget} is less than that"):
        resume(run, budget)
    assert _files(run) == before and not (tmp_path / "summary.jsonl").exists()
    assert issubclass(TrainingError, UserInputError)  # sdn3d-train: one line, exit 2


def test_an_inference_export_is_refused_where_a_training_checkpoint_is_needed(trained, tmp_path):
    run = _copy(trained, tmp_path)
    shutil.copy(run / "checkpoints" / "inference.pt", run / "checkpoints" / "last.ckpt")  # the mistake
    before = _files(run)
    with pytest.raises(TrainingError, match=r"its checkpoint .*last\.ckpt' is an sdn3d inference export .*training "
                                            r"can only continue from a Lightning training checkpoint"):
        resume(run, "trainer.max_epochs=3")
    assert _files(run) == before
    # ckpt_path= an export, into a new run: refused before the run directory is made
    new = tmp_path / "new"
    overrides = [*TRAIN, f"data.root={tmp_path}", f"run_dir={new}", f"summary_file={tmp_path / 'summary.jsonl'}",
                 f"ckpt_path={trained / 'checkpoints' / 'inference.pt'}", "trainer.max_epochs=3"]
    with pytest.raises(TrainingError, match=r"ckpt_path '.*inference\.pt' is an sdn3d inference export"):
        run_training(compose_train(overrides), overrides)
    assert not new.exists() and not (tmp_path / "summary.jsonl").exists()
    # ...and another branch's training checkpoint
    other = torch.load(trained / "checkpoints" / "last.ckpt", map_location="cpu", weights_only=True)
    other["state_dict"] = {"generator.model.0.weight": torch.zeros(1)}
    torch.save(other, tmp_path / "textural.ckpt")
    overrides[-2] = f"ckpt_path={tmp_path / 'textural.ckpt'}"
    with pytest.raises(TrainingError, match=r"textural\.ckpt' holds the textural branch's weights, not the semantic"):
        run_training(compose_train(overrides), overrides)
    assert not new.exists()


def test_resuming_a_finished_run_without_a_larger_budget_changes_nothing(trained, tmp_path, caplog):
    run = _copy(trained, tmp_path)
    before = _files(run)
    earlier = json.loads((run / "summary.json").read_text())
    with caplog.at_level(logging.WARNING, logger="sdn3d.training.resume"):
        summary = resume(run)
    assert summary == earlier and _files(run) == before and not (tmp_path / "summary.jsonl").exists()
    assert "nothing to do: the run has trained 2 epoch(s), 2 optimiser step(s), all of its budget " \
           "(trainer.max_epochs=2)" in caplog.text and "trainer.max_epochs=12" in caplog.text


def test_a_failed_resume_keeps_the_finished_runs_summary_and_logs_the_failure(trained, tmp_path):
    run = _copy(trained, tmp_path)
    summary_before = (run / "summary.json").read_bytes()
    with pytest.raises(UserInputError, match="missing_data"):  # data.root= applies: the run now reads there
        resume(run, "trainer.max_epochs=3", f"data.root={tmp_path / 'missing_data'}")
    assert (run / "summary.json").read_bytes() == summary_before
    attempts = [json.loads(line) for line in (run / "summary_log.jsonl").read_text().splitlines()]
    assert [a["status"] for a in attempts] == ["ok", "failed"] and "missing_data" in attempts[-1]["error"]
    assert attempts[-1]["resume_overrides"][-1] == f"data.root={tmp_path / 'missing_data'}"
    line = json.loads((tmp_path / "summary.jsonl").read_text().splitlines()[-1])
    assert line["status"] == "failed" and line["run_dir"] == str(run.resolve())
    chosen, _ = find_run_checkpoints(run)  # run= still serves the finished run
    assert chosen["semantic"]["checkpoint"] == str((run / "checkpoints" / "best-epoch001.ckpt").resolve()) or \
        chosen["semantic"]["checkpoint"].startswith(str(run.resolve()))


def test_a_resume_that_trains_on_records_the_run_it_continues(trained, tmp_path):
    run = _copy(trained, tmp_path)
    earlier = json.loads((run / "summary.json").read_text())
    summary = resume(run, "trainer.max_epochs=3", "threads=1")
    assert summary["status"] == "ok" and summary["epoch"] == 3 and summary["global_step"] == 3
    assert summary["overrides"] == earlier["overrides"] and summary["experiment"] == earlier["experiment"]
    assert summary["resume_overrides"] == [f"resume={run}", f"summary_file={tmp_path / 'summary.jsonl'}",
                                           "trainer.max_epochs=3", "threads=1"]
    assert json.loads((run / "summary.json").read_text()) == summary
    assert [json.loads(x)["epoch"] for x in (run / "summary_log.jsonl").read_text().splitlines()] == [2, 3]
    assert torch.get_num_threads() == 1  # threads=1 (no dot) applied



def test_a_run_killed_before_its_summary_resumes_with_its_first_command_line(trained, tmp_path):
    """A run killed while testing (a lent machine's time limit) has no summary.json: its resume records the
    experiment and overrides of the command that started it, read from the `.hydra/` record of its first attempt
    (before: experiment null, overrides []), and the monitor of its own config."""
    run = _copy(trained, tmp_path)
    (run / "summary.json").unlink()
    first = ["branch=semantic", "experiment=demo", f"data.root={tmp_path}", "seed=0", "threads=1"]
    (run / ".hydra").mkdir(exist_ok=True)
    (run / ".hydra" / "overrides.yaml").write_text(OmegaConf.to_yaml(OmegaConf.create(first)))
    (run / ".hydra" / "hydra.yaml").write_text(OmegaConf.to_yaml(OmegaConf.create(
        {"hydra": {"runtime": {"choices": {"experiment": "demo", "branch": "semantic"}}}})))
    summary = resume(run, "trainer.max_epochs=3")
    assert summary["status"] == "ok" and summary["epoch"] == 3
    assert summary["experiment"] == "demo" and summary["overrides"] == first
    assert summary["resume_overrides"][0] == f"resume={run}"
    saved = OmegaConf.load(run / "config.yaml")
    assert summary["monitor"] == saved.monitor and summary["selected_by"].startswith(saved.monitor)

def test_every_resume_override_is_applied_or_refused(trained, tmp_path):
    run = _copy(trained, tmp_path)
    cfg = OmegaConf.create({"resume": str(run), "summary_file": str(tmp_path / "default.jsonl")})

    def resolved(*over: str):
        return resolve_resume(cfg, [f"resume={run}", *over])

    got = resolved("threads=1", f"summary_file={tmp_path / 'side.jsonl'}", "seed=7",
                   f"data.root={tmp_path / 'elsewhere'}", "~callbacks.step_checkpoint", "+trainer.min_epochs=1",
                   "++trainer.max_time=null", "fault.nonfinite=skip")
    assert got.threads == 1 and got.summary_file == str(tmp_path / "side.jsonl") and got.seed == 7
    assert "step_checkpoint" not in got.callbacks and got.trainer.min_epochs == 1
    # settings that follow from others follow the override, as in a new run
    assert got.datamodule.data.root == str(tmp_path / "elsewhere") and got.datamodule.seed == 7
    assert got.model.nonfinite == "skip"
    assert resolved().summary_file == str(tmp_path / "default.jsonl")  # summary_file: this command's
    refused = {"branch=geometric": r"'branch' .*group's choice.*can not change on resume",
               "data=synth": r"'data' is a config group \(or a section of settings\)",
               "callbacks=none": r"'callbacks' is a config group",
               f"run_dir={tmp_path}": r"run_dir can not be given: a resumed run writes into its own directory",
               f"ckpt_path={run / 'checkpoints' / 'best-epoch001.ckpt'}": r"ckpt_path can not be given",
               "trainer.max_epoch=3": r"the run's config has no setting 'trainer.max_epoch'; a typo\? To add a "
                                      r"setting, write \+trainer.max_epoch=3",
               "+seed=3": r"already has 'seed': drop the '\+' to change it",
               "~trainer.no_such_key": r"has no 'trainer.no_such_key' to delete",
               "trainer.max_epochs=[1": r"bad command line override"}
    for override, message in refused.items():
        with pytest.raises(TrainingError, match=message):
            resolved(override)
