"""Issue 42, training-data loss: a run's outputs are never replaced or lost without the user asking.

- ``last.ckpt`` is written at every epoch's end, not only when the monitored metric improved (a killed run lost
  every epoch since the last improvement).
- A new ``sdn3d-train`` into a directory that holds a run is refused (its checkpoints, ``inference.pt`` and
  ``summary.json`` were replaced without asking); ``overwrite=true`` replaces it.
- A training refused before it starts (the run directory's lock, ``ckpt_path=``) leaves no new run directory and
  does not touch another run's ``.hydra/`` record.
- A refused ``sdn3d-train`` answers before it imports Lightning (about ten seconds), and torch where the refusal
  reads no checkpoint.
- ``+max_epochs=2`` (Hydra's own advice for a key it does not know) is refused, naming ``trainer.max_epochs``.
- ``run=`` names a run's missing best checkpoint before it loads the last one instead.
- ``sdn3d-export-weights`` on a full disk: one line saying so, exit 2, nothing half-written.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import lightning as L
import pytest
import torch
from faults.disk import full_disk
from hydra import compose, initialize_config_dir
from hydra.utils import instantiate

REPO = Path(__file__).resolve().parents[1]


def _compose(overrides: list[str]):
    with initialize_config_dir(config_dir=str(REPO / "conf"), version_base="1.3"):
        return compose("train", overrides=overrides)


class _Tiny(L.LightningModule):
    """A linear model whose validation loss only ever gets worse after the first epoch."""

    def __init__(self) -> None:
        super().__init__()
        self.layer = torch.nn.Linear(2, 1)

    def training_step(self, batch, batch_idx):
        return self.layer(batch[0]).sum()

    def validation_step(self, batch, batch_idx):
        self.log("val/loss", float(self.current_epoch))

    def configure_optimizers(self):
        return torch.optim.SGD(self.parameters(), lr=0.01)


def _loader():
    data = torch.utils.data.TensorDataset(torch.ones(2, 2))
    return torch.utils.data.DataLoader(data, batch_size=2)


def test_last_ckpt_is_written_every_epoch_even_without_an_improvement(tmp_path):
    cfg = _compose([f"run_dir={tmp_path}", "monitor=val/loss", "monitor_mode=min"])
    callback = instantiate(cfg.callbacks.model_checkpoint)
    trainer = L.Trainer(max_epochs=3, callbacks=[callback], logger=False, enable_progress_bar=False,
                        enable_model_summary=False, num_sanity_val_steps=0)
    trainer.fit(_Tiny(), train_dataloaders=_loader(), val_dataloaders=_loader())
    last = torch.load(tmp_path / "checkpoints" / "last.ckpt", weights_only=True)
    assert last["global_step"] == 3 and last["epoch"] == 2  # before: step 1, the only improvement
    assert sorted(p.name for p in (tmp_path / "checkpoints").iterdir()) == ["best-epoch000.ckpt", "last.ckpt"]
    assert callback.state_key.startswith("ModelCheckpoint{")  # resumes runs written with the plain callback


def _checkpoint(tmp_path: Path) -> Path:
    from helpers.tiny_models import write_checkpoints

    return Path(write_checkpoints(tmp_path / "ckpt")["semantic"])


def test_export_weights_on_a_full_disk_says_so_in_one_line_and_writes_nothing(tmp_path, capsys):
    from sdn3d.cli.export_weights import main

    checkpoint = _checkpoint(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "semantic.pt").write_bytes(b"earlier")
    before = sorted(p.name for p in checkpoint.parent.iterdir())
    with full_disk(room=4096):
        code = main([str(checkpoint), str(out / "semantic.pt"), "--overwrite"])
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "the disk is full" in err and str(out / "semantic.pt") in err, err
    assert sorted(p.name for p in out.iterdir()) == ["semantic.pt"] and (out / "semantic.pt").read_bytes() == b"earlier"
    assert sorted(p.name for p in checkpoint.parent.iterdir()) == before


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_a_new_run_into_a_directory_holding_a_run_is_refused_and_touches_nothing(tmp_path):
    from lightning_modules.train import run_training
    from sdn3d.training.errors import TrainingError
    from sdn3d.training.rundir import check_new_run_dir

    run = tmp_path / "run"
    (run / "checkpoints").mkdir(parents=True)
    for name, text in (("config.yaml", "seed: 0\n"), ("summary.json", '{"status": "ok"}'),
                       ("checkpoints/last.ckpt", "weights"), ("checkpoints/inference.pt", "export")):
        (run / name).write_text(text)
    before = _files(run)
    overrides = ["branch=semantic", f"run_dir={run}", f"summary_file={tmp_path / 'summary.jsonl'}"]
    with pytest.raises(TrainingError, match=rf"run directory '{run}' already holds a run \(config.yaml, summary.json, "
                                            rf"checkpoints\).*resume={run}.*overwrite=true"):
        run_training(_compose(overrides), overrides)
    assert _files(run) == before and sorted(p.name for p in run.iterdir()) == ["checkpoints", "config.yaml",
                                                                              "summary.json"]
    assert not (tmp_path / "summary.jsonl").exists()
    check_new_run_dir(_compose([*overrides, "overwrite=true"]))  # the explicit switch lets it through
    check_new_run_dir(_compose(["branch=semantic", f"run_dir={tmp_path / 'new'}"]))


@pytest.mark.parametrize("override", ["+max_epochs=2", "+batch_size=4"])
def test_a_top_level_setting_nothing_reads_is_refused_naming_the_intended_one(tmp_path, override):
    from lightning_modules.train import run_training
    from sdn3d.training.errors import TrainingError

    overrides = ["branch=semantic", f"run_dir={tmp_path / 'run'}", f"summary_file={tmp_path / 's.jsonl'}", override]
    meant = {"+max_epochs=2": r"did you mean trainer\.max_epochs=2\?",
             "+batch_size=4": r"did you mean datamodule\.batch_size=4\?"}[override]
    with pytest.raises(TrainingError, match=rf"'\{override}': sdn3d-train has no top-level setting .*{meant}"):
        run_training(_compose(overrides), overrides)
    assert not (tmp_path / "run").exists()


def _cli(args: list[str], cwd: Path, python: tuple[str, ...] = ()) -> subprocess.CompletedProcess:
    path = os.pathsep.join([str(REPO / "src"), str(REPO), str(REPO / "tests")])
    env = {**os.environ, "PYTHONPATH": path, "OMP_NUM_THREADS": "1"}
    return subprocess.run([sys.executable, *python, "-m", "sdn3d.cli.train", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def _imported_packages(importtime: str) -> set[str]:
    """The top-level packages a process imported, from what ``python -X importtime`` wrote on its stderr."""
    return {line.rsplit("|", 1)[1].strip().split(".")[0] for line in importtime.splitlines()
            if line.startswith("import time:") and line.count("|") == 2}


@pytest.mark.parametrize("refusal", ["a run directory holding a run", "a ckpt_path that is no training checkpoint"])
def test_a_refused_training_answers_before_importing_lightning(tmp_path, refusal):
    run = tmp_path / "run"
    args = ["branch=semantic", f"hydra.run.dir={run}", f"summary_file={tmp_path / 's.jsonl'}"]
    if refusal == "a run directory holding a run":
        run.mkdir()
        (run / "summary.json").write_text('{"status": "ok"}')
        said, left = f"run directory '{run}' already holds a run (summary.json)", ["run"]
    else:
        torch.save({"state_dict": {}}, tmp_path / "weights.pt")
        args.append(f"ckpt_path={tmp_path / 'weights.pt'}")
        said, left = "is not a Lightning training checkpoint (it lacks 'pytorch-lightning_version'", ["weights.pt"]
    result = _cli(args, tmp_path, python=("-X", "importtime"))
    last = [line for line in result.stderr.strip().splitlines() if not line.startswith("import time:")][-1]
    assert result.returncode == 2 and last.startswith("sdn3d-train: error: ") and said in last, result.stderr[-2000:]
    imported = _imported_packages(result.stderr)
    assert "hydra" in imported and not {"lightning", "pytorch_lightning"} & imported  # before: both imported
    assert ("torch" in imported) == (refusal != "a run directory holding a run")  # torch only to read the file
    assert sorted(p.name for p in tmp_path.iterdir()) == left  # no new run directory, no summary_file
    if run.exists():  # the run it refused to replace, as it was (Hydra's train.log of this job beside it)
        assert (run / "summary.json").read_text() == '{"status": "ok"}' and not (run / ".hydra").exists()


def test_a_refused_training_leaves_no_run_directory_and_no_other_runs_hydra_record(tmp_path):
    from sdn3d.io import writer_lock
    from sdn3d.training.locks import RUN_LOCK

    fresh = tmp_path / "fresh"
    result = _cli(["branch=semantic", f"hydra.run.dir={fresh}", f"ckpt_path={tmp_path / 'missing.ckpt'}",
                   f"summary_file={tmp_path / 's.jsonl'}"], tmp_path)
    assert result.returncode == 2 and "missing.ckpt' does not exist" in result.stderr, result.stderr
    assert not fresh.exists()  # before: an empty run directory (Hydra's .hydra/ and train.log)

    running = tmp_path / "running"
    (running / ".hydra").mkdir(parents=True)
    (running / ".hydra" / "config.yaml").write_text("the running run's record\n")
    with writer_lock(running / RUN_LOCK, f"run directory {str(running)!r}"):
        result = _cli(["branch=semantic", f"hydra.run.dir={running}", f"summary_file={tmp_path / 's.jsonl'}"],
                      tmp_path)
    assert result.returncode == 2 and "is being written by another sdn3d process" in result.stderr, result.stderr
    assert (running / ".hydra" / "config.yaml").read_text() == "the running run's record\n"
    assert sorted(p.name for p in (running / ".hydra").iterdir()) == ["config.yaml"]


def test_run_names_a_missing_best_checkpoint_before_using_the_last(tmp_path, caplog):
    import json
    import logging

    from sdn3d.runs import find_run_checkpoints

    run = tmp_path / "run"
    checkpoint = _checkpoint(tmp_path)
    (run / "checkpoints").mkdir(parents=True)
    (run / "checkpoints" / "last.ckpt").write_bytes(checkpoint.read_bytes())
    (run / "summary.json").write_text(json.dumps({
        "branch": "semantic", "status": "ok", "run_dir": str(run), "finished": "2026-11-28T00:00:00+00:00",
        "best_ckpt": str(run / "checkpoints" / "best-epoch003.ckpt"), "last_ckpt": str(run / "checkpoints/last.ckpt")}))
    with caplog.at_level(logging.WARNING, logger="sdn3d.runs"):
        chosen, _ = find_run_checkpoints(run)
    assert chosen["semantic"]["which"] == "last"
    assert f"records the best checkpoint {run / 'checkpoints' / 'best-epoch003.ckpt'}, which is missing: using " \
           f"its last checkpoint {run / 'checkpoints' / 'last.ckpt'} instead" in caplog.text  # before: nothing said
