"""Issue 28, one vocabulary across the commands: ``sdn3d-train`` takes ``threads=`` as ``sdn3d-edit``,
``sdn3d-bench`` and ``sdn3d-demo`` do.

Before: ``sdn3d-train threads=1`` failed (``Could not override 'threads'``: the key was ``torch_threads``), and
``torch_threads=0`` or ``=-3`` was silently ignored. Now: ``threads`` is a positive integer or null (PyTorch's
default); anything else stops before the run starts (exit 2, one line naming the setting). The demo passes
``threads=`` to the training runs it starts.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
import torch
from hydra import compose, initialize_config_dir
from omegaconf import OmegaConf

from lightning_modules.fit import configure_process
from lightning_modules.train import run_training
from sdn3d.training.errors import TrainingError
from sdn3d.training.start import check_threads

CONF = Path(__file__).resolve().parents[1] / "conf"


def _compose(overrides: list[str], name: str = "train"):
    from sdn3d.cli._schemas import register

    register(name)  # the schemas conf/<name>.yaml names first (conf/demo.yaml: its structured schema)
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"):
        return compose(name, overrides=overrides)


def _train(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    environ = {k: v for k, v in os.environ.items() if k != "HYDRA_FULL_ERROR"} | {"OMP_NUM_THREADS": "1"}
    return subprocess.run([sys.executable, "-m", "sdn3d.cli.train", *args], cwd=cwd, env=environ,
                          capture_output=True, text=True, timeout=300)


def test_train_composes_with_threads_and_applies_it():
    cfg = _compose(["threads=1", "branch=semantic", "experiment=demo", "run_dir=/tmp/unused"])
    assert cfg.threads == 1 and "torch_threads" not in cfg
    assert _compose(["run_dir=/tmp/unused"]).threads is None  # default: PyTorch's own
    check_threads(cfg)  # accepted
    before = torch.get_num_threads()
    try:
        torch.set_num_threads(2)
        configure_process(cfg)
        assert torch.get_num_threads() == 1
    finally:
        torch.set_num_threads(before)


@pytest.mark.parametrize("value", [0, -3, 1.5, "two", True])
def test_threads_other_than_a_positive_integer_or_null_is_refused(value):
    cfg = OmegaConf.create({"threads": value})
    with pytest.raises(TrainingError, match=r"threads must be a positive integer .* or null .*got "):
        check_threads(cfg)
    check_threads(OmegaConf.create({"threads": None}))
    check_threads(OmegaConf.create({"threads": 4}))


def test_run_training_refuses_bad_threads_before_writing_anything(tmp_path):
    cfg = _compose(["threads=0", f"run_dir={tmp_path / 'run'}", f"summary_file={tmp_path / 'summary.jsonl'}"])
    with pytest.raises(TrainingError, match="threads must be a positive integer"):
        run_training(cfg, ["threads=0"])
    assert list(tmp_path.iterdir()) == []


def test_sdn3d_train_threads_0_exits_2_in_one_line(tmp_path):
    proc = _train(["threads=0", f"hydra.run.dir={tmp_path / 'run'}", f"summary_file={tmp_path / 's.jsonl'}"],
                  tmp_path)
    assert proc.returncode == 2, proc.stderr
    lines = [line for line in proc.stderr.strip().splitlines() if "sdn3d-train: error:" in line]
    assert lines == ["sdn3d-train: error: threads must be a positive integer (torch CPU threads) or null for "
                     "PyTorch's default, got 0"], proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "s.jsonl").exists() and not (tmp_path / "run" / "summary.json").exists()


@pytest.mark.slow  # ~8 s of CPU (Lightning loads before the data is looked for): in the default run
# test_full_demo_tiny_budget's three sdn3d-train processes get threads=1 (test_the_demo_passes_threads_to_sdn3d_train)
# and train, and test_train_composes_with_threads_and_applies_it composes and applies threads=1
def test_sdn3d_train_accepts_threads_1(tmp_path):
    """``threads=1`` gets past composition and the check (the run then stops on the missing data, exit 2, naming
    the data, not the setting)."""
    missing = tmp_path / "no_data"
    proc = _train(["threads=1", f"data.root={missing}", f"hydra.run.dir={tmp_path / 'run'}",
                   f"summary_file={tmp_path / 's.jsonl'}", "logger=none"], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "threads" not in proc.stderr and str(missing) in proc.stderr, proc.stderr


def test_sdn3d_train_refuses_the_old_threads_key(tmp_path):
    """The old ``torch_threads=`` is an unknown key (refused while composing, before Lightning loads)."""
    old = _train(["torch_threads=1", f"hydra.run.dir={tmp_path / 'old'}"], tmp_path)
    assert old.returncode == 2 and "Could not override 'torch_threads'" in old.stderr, old.stderr


def test_the_demo_passes_threads_to_sdn3d_train(tmp_path):
    from sdn3d.cli.demo import _train_command

    demo = _compose(["threads=1"], "demo")
    cmd = _train_command("semantic", demo, tmp_path / "data", tmp_path / "runs")
    assert "threads=1" in cmd and not any(o.startswith("torch_threads=") for o in cmd)
    composed = _compose([o for o in cmd[3:] if not o.startswith("hydra.")] + [f"run_dir={tmp_path}"])
    assert composed.threads == 1


def test_threads_later_takes_more_threads_from_its_epoch_on_and_builds_its_callback(tmp_path):
    """``threads_later={after_epochs: E, threads: T}``: the run's threads for its first E epochs, T from then on
    (sdn3d-demo's semantic training: fixed by epoch, never by timing); refused, naming the key, when malformed."""
    import lightning as L
    from torch.utils.data import DataLoader, TensorDataset

    from lightning_modules.callbacks import ThreadsLaterCallback
    from lightning_modules.fit import build_objects
    from sdn3d.training.start import ThreadsLater, threads_later

    cfg = _compose(["threads=1", "branch=semantic", "experiment=demo", f"run_dir={tmp_path / 'run'}",
                    "threads_later={after_epochs:2,threads:2}", "logger=none"])
    assert threads_later(cfg) == ThreadsLater(2, 2)
    check_threads(cfg)
    assert threads_later(_compose(["run_dir=/tmp/unused"])) is None  # default: `threads` throughout
    made = [c for c in build_objects(cfg).trainer.callbacks if isinstance(c, ThreadsLaterCallback)]
    assert [c.later for c in made] == [ThreadsLater(2, 2)]
    for bad, key in (({"after_epochs": -1, "threads": 2}, "after_epochs"),
                     ({"after_epochs": 1, "threads": 0}, "threads"),
                     ({"after_epochs": 1.5, "threads": 2}, "after_epochs"), ({"threads": 2}, "threads_later")):
        with pytest.raises(TrainingError, match=key):
            check_threads(OmegaConf.create({"threads": 1, "threads_later": bad}))

    seen = []

    class Tiny(L.LightningModule):
        def __init__(self) -> None:
            super().__init__()
            self.layer = torch.nn.Linear(2, 1)

        def training_step(self, batch, batch_idx):
            seen.append((self.current_epoch, torch.get_num_threads()))
            return self.layer(batch[0]).pow(2).mean()

        def configure_optimizers(self):
            return torch.optim.SGD(self.parameters(), lr=0.1)

    before = torch.get_num_threads()
    try:
        torch.set_num_threads(1)
        trainer = L.Trainer(max_epochs=4, callbacks=[ThreadsLaterCallback(ThreadsLater(2, 2))], logger=False,
                            enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False,
                            default_root_dir=tmp_path)
        trainer.fit(Tiny(), DataLoader(TensorDataset(torch.randn(4, 2)), batch_size=4))
    finally:
        torch.set_num_threads(before)
    assert seen == [(0, 1), (1, 1), (2, 2), (3, 2)]
