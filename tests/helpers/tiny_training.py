"""A tiny ``sdn3d-train`` run of the semantic branch (1 batch per part, 160x64) and its resume, through
``lightning_modules.train.run_training`` with configs composed as the CLI does (the reliability tests)."""

from __future__ import annotations

from pathlib import Path

from hydra import compose, initialize_config_dir

from lightning_modules.train import run_training

REPO = Path(__file__).resolve().parents[2]
#: Overrides of the tiny semantic run.
TINY_SEMANTIC = ["branch=semantic", "experiment=demo", "data.image_size=[160,64]", "trainer.limit_train_batches=1",
                 "trainer.limit_val_batches=1", "trainer.limit_test_batches=1", "trainer.enable_progress_bar=false",
                 "~callbacks.progress_bar", "logger=csv", "datamodule.batch_size=2",
                 # a narrow DRN (tests/helpers/tiny_models.py's widths): 0.3 MB checkpoints instead of 130 MB
                 "model.channels=[4,4,8,8,16,16,16,16]", "model.head_channels=8"]


def compose_train(overrides: list[str]):
    """``conf/train.yaml`` with ``overrides``, as ``sdn3d-train`` composes it."""
    with initialize_config_dir(config_dir=str(REPO / "conf"), version_base="1.3"):
        return compose("train", overrides=overrides)


def train_tiny(root: Path, run_dir: Path, *extra: str) -> dict:
    """Two epochs of the tiny semantic run on the dataset at ``root`` into ``run_dir`` (summary beside it)."""
    overrides = [*TINY_SEMANTIC, f"data.root={root}", f"run_dir={run_dir}",
                 f"summary_file={run_dir.parent / 'summary.jsonl'}", "trainer.max_epochs=2", *extra]
    return run_training(compose_train(overrides), overrides)


def resume(run: Path, *extra: str) -> dict:
    """``resume=<run>`` with ``extra`` overrides (summary beside the run)."""
    overrides = [f"resume={run}", f"summary_file={run.parent / 'summary.jsonl'}", *extra]
    return run_training(compose_train(overrides), overrides)
