"""Shared plumbing of the three branch LightningModules: loss guard and TensorBoard images.

Training logic stays in each module; this base only gives them one policy for non-finite
losses (set by ``sdn3d-train``'s ``fault.nonfinite``) and one way to write image grids.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Any

import lightning as L
import torch
from torch import Tensor

__all__ = ["BranchModule", "NonFiniteLossError", "image_grid"]

log = logging.getLogger(__name__)

NONFINITE_POLICIES = ("stop", "skip")


class NonFiniteLossError(RuntimeError):
    """A training loss became NaN or infinite (policy ``stop``)."""


def plain_hparams(value: Any) -> Any:
    """Hydra / OmegaConf containers (and tuples) -> plain dicts and lists, so the hyper-parameters a
    checkpoint stores load with ``torch.load(weights_only=True)``."""
    if isinstance(value, Mapping):
        return {str(k): plain_hparams(v) for k, v in value.items()}
    if isinstance(value, Sequence) and not isinstance(value, str):
        return [plain_hparams(v) for v in value]
    return value


def image_grid(rows: list[Tensor], pad: int = 2) -> Tensor:
    """Tile images into one ``(3, H', W')`` grid: one column per entry of ``rows``, one row per sample.

    Args:
        rows: tensors ``(N, C, H, W)`` (C = 1 or 3, values in [0, 1]), all of one ``N, H, W``;
            e.g. ``[input, prediction, target]`` gives "input | prediction | target" rows.
        pad: white padding between tiles, in pixels.
    """
    if not rows:
        raise ValueError("image_grid needs at least one image batch")
    n, _, h, w = rows[0].shape
    for r in rows:
        if r.dim() != 4 or r.shape[0] != n or r.shape[2:] != (h, w) or r.shape[1] not in (1, 3):
            raise ValueError(f"image_grid: every batch must be (N, 1|3, H, W) with N={n}, H={h}, W={w}; "
                             f"got {tuple(r.shape)}")
    cols = len(rows)
    grid = torch.ones(3, n * (h + pad) + pad, cols * (w + pad) + pad)
    for c, batch in enumerate(rows):  # a handful of columns: the loop is over panels, not pixels
        batch = batch.detach().float().cpu().clamp(0, 1).expand(-1, 3, -1, -1)
        for i in range(n):
            top, left = pad + i * (h + pad), pad + c * (w + pad)
            grid[:, top:top + h, left:left + w] = batch[i]
    return grid


class BranchModule(L.LightningModule):
    """Base class of SemanticModule, GeometricModule and TexturalModule.

    Args:
        nonfinite: what a non-finite training loss does: ``'stop'`` raises
            :class:`NonFiniteLossError` (the last good checkpoint stays), ``'skip'`` drops the batch.
            ``sdn3d-train`` passes ``fault.nonfinite`` (conf/train.yaml); not a hyperparameter.

    Attributes:
        nonfinite: the policy above.
        skipped_batches: batches dropped by the ``'skip'`` policy so far.
    """

    nonfinite: str = "stop"

    def __init__(self, nonfinite: str = "stop") -> None:
        super().__init__()
        self.nonfinite = nonfinite
        self.skipped_batches = 0

    def guard_loss(self, loss: Tensor, name: str = "loss") -> bool:
        """True when ``loss`` is finite. Otherwise raise (policy stop) or count and return False (skip).

        Automatic optimisation: ``if not self.guard_loss(loss): return None`` skips the step.
        Manual optimisation: skip ``manual_backward``/``step`` when it returns False.
        """
        if bool(torch.isfinite(loss.detach()).all()):
            return True
        if self.nonfinite not in NONFINITE_POLICIES:
            raise ValueError(f"fault.nonfinite must be one of {NONFINITE_POLICIES}, got {self.nonfinite!r}")
        where = f"{type(self).__name__} {name} = {loss.detach().cpu().tolist()} at epoch {self.current_epoch}, " \
                f"global step {self.global_step}"
        if self.nonfinite == "stop":
            raise NonFiniteLossError(
                f"non-finite training loss: {where}. The run stops; the last good checkpoint is kept. "
                "Set fault.nonfinite=skip to drop such batches instead.")
        self.skipped_batches += 1
        log.warning("skipping batch with non-finite loss: %s (%d skipped so far)", where, self.skipped_batches)
        self.log("train/skipped_batches", float(self.skipped_batches), on_step=True, on_epoch=False)
        return False

    @property
    def tensorboard(self):
        """The TensorBoard ``SummaryWriter`` of the first TensorBoard logger, or None."""
        from lightning.pytorch.loggers import TensorBoardLogger

        for logger in getattr(self.trainer, "loggers", []) if self._trainer is not None else []:
            if isinstance(logger, TensorBoardLogger):
                return logger.experiment
        return None

    def log_image_grid(self, tag: str, rows: list[Tensor], step: int | None = None) -> bool:
        """Write :func:`image_grid` of ``rows`` to TensorBoard (no-op without a TensorBoard logger)."""
        writer = self.tensorboard
        if writer is None or (self._trainer is not None and self.trainer.sanity_checking):
            return False
        writer.add_image(tag, image_grid(rows), global_step=self.global_step if step is None else step)
        return True
