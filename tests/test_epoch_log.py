"""EpochLog: one line per epoch, validation metrics only on epochs that validated."""

from __future__ import annotations

import logging

import lightning as L
import torch
from torch.utils.data import DataLoader, TensorDataset

from lightning_modules.callbacks import EpochLog


class _Tiny(L.LightningModule):
    def __init__(self) -> None:
        super().__init__()
        self.layer = torch.nn.Linear(2, 1)

    def training_step(self, batch, batch_idx):
        loss = self.layer(batch[0]).pow(2).mean()
        self.log("train/loss", loss, on_epoch=True, on_step=False)
        return loss

    def validation_step(self, batch, batch_idx):
        self.log("val/score", float(self.current_epoch + 1))

    def configure_optimizers(self):
        return torch.optim.SGD(self.parameters(), lr=0.1)


def _loader() -> DataLoader:
    return DataLoader(TensorDataset(torch.randn(8, 2)), batch_size=4)


def test_epoch_lines_show_validation_only_when_it_ran(tmp_path, caplog):
    trainer = L.Trainer(max_epochs=4, check_val_every_n_epoch=2, callbacks=[EpochLog()], logger=False,
                        enable_checkpointing=False, enable_progress_bar=False, enable_model_summary=False,
                        default_root_dir=tmp_path, num_sanity_val_steps=1)
    with caplog.at_level(logging.INFO, logger="sdn3d.train"):
        trainer.fit(_Tiny(), _loader(), _loader())
    lines = [r.getMessage() for r in caplog.records if r.getMessage().startswith("epoch ")]
    assert [line.split(" done")[0] for line in lines] == ["epoch 1/4", "epoch 2/4", "epoch 3/4", "epoch 4/4"]
    assert all("train/loss" in line for line in lines), lines
    # Validation ran after epochs 2 and 4 (its value is the 0-based epoch + 1); epochs 1 and 3 must not
    # repeat the sanity check's or epoch 2's value.
    assert "val/" not in lines[0] and "val/" not in lines[2], lines
    assert "val/score 2" in lines[1] and "val/score 4" in lines[3], lines


class _ManyTerms(_Tiny):
    """A joint stage's line: more training terms than a line's share, then the validation figure."""

    def training_step(self, batch, batch_idx):
        loss = self.layer(batch[0]).pow(2).mean()
        for i in range(15):
            self.log(f"train/term_{i:02d}", loss + i, on_epoch=True, on_step=False)
        return loss


def test_validation_figures_keep_their_place_beside_many_training_terms(tmp_path, caplog):
    trainer = L.Trainer(max_epochs=1, callbacks=[EpochLog(max_metrics=12)], logger=False, enable_checkpointing=False,
                        enable_progress_bar=False, enable_model_summary=False, default_root_dir=tmp_path,
                        num_sanity_val_steps=0)
    with caplog.at_level(logging.INFO, logger="sdn3d.train"):
        trainer.fit(_ManyTerms(), _loader(), _loader())
    (line,) = [r.getMessage() for r in caplog.records if r.getMessage().startswith("epoch ")]
    assert "val/score 1" in line, line
    assert "train/term_11" in line and "train/term_12" not in line, line  # 12 training terms at most
    assert line.index("train/term_00") < line.index("val/score"), line  # training first, as the keys order them
