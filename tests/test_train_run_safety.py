"""Issue 42, training-data loss: a run's outputs are never replaced or lost without the user asking.

- ``last.ckpt`` is written at every epoch's end, not only when the monitored metric improved (a killed run lost
  every epoch since the last improvement).
- A new ``sdn3d-train`` into a directory that holds a run is refused (its checkpoints, ``inference.pt`` and
  ``summary.json`` were replaced without asking); ``overwrite=true`` replaces it.
- A training refused before it starts (the run directory's lock, ``ckpt_path=``) leaves no new run directory and
  does not touch another run's ``.hydra/`` record.
- ``+max_epochs=2`` (Hydra's own advice for a key it does not know) is refused, naming ``trainer.max_epochs``.
- ``run=`` names a run's missing best checkpoint before it loads the last one instead.
- ``sdn3d-export-weights`` on a full disk: one line saying so, exit 2, nothing half-written.
"""

from __future__ import annotations

from pathlib import Path

import lightning as L
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
