"""Callbacks the training-operation tests add through Hydra overrides (``+callbacks.x._target_=...``)."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import lightning as L
import torch


class KillAtStep(L.Callback):
    """SIGKILL the training process right after optimiser step ``step`` (a hard crash, no cleanup).

    Armed only while the environment variable ``env`` is set: the resumed run (same saved config,
    so the same callbacks) runs without it.
    """

    def __init__(self, step: int, env: str = "SDN3D_TEST_KILL") -> None:
        self.step = int(step)
        self.armed = bool(os.environ.get(env))

    def on_train_batch_end(self, trainer, pl_module, outputs, batch, batch_idx) -> None:
        if self.armed and trainer.global_step >= self.step:
            os.kill(os.getpid(), signal.SIGKILL)


class SaveRankWeights(L.Callback):
    """Each DDP rank writes its initial and final parameters to ``<dirpath>/rank<r>.pt``."""

    def __init__(self, dirpath: str) -> None:
        self.dirpath = dirpath

    def on_train_start(self, trainer, pl_module) -> None:
        self.initial = {k: v.detach().cpu().clone() for k, v in pl_module.state_dict().items()}

    def on_train_end(self, trainer, pl_module) -> None:
        Path(self.dirpath).mkdir(parents=True, exist_ok=True)
        state = {k: v.detach().cpu().clone() for k, v in pl_module.state_dict().items()}
        torch.save({"state": state, "initial": self.initial, "step": trainer.global_step},
                   Path(self.dirpath) / f"rank{trainer.global_rank}.pt")


class PoisonBatchAtStep(L.Callback):
    """Fill the float tensors of one batch (first at or after step ``step``) with NaN: its loss goes non-finite."""

    def __init__(self, step: int) -> None:
        self.step = int(step)
        self.done = False

    def on_train_batch_start(self, trainer, pl_module, batch, batch_idx) -> None:
        if not self.done and trainer.global_step >= self.step and isinstance(batch, dict):
            self.done = True
            for value in batch.values():
                if isinstance(value, torch.Tensor) and value.is_floating_point():
                    value.fill_(float("nan"))
