"""Shared plumbing of the three branch LightningModules: loss guard and TensorBoard images.

Training logic stays in each module; this base only gives them one policy for non-finite
losses (set by ``sdn3d-train``'s ``fault.nonfinite`` and ``fault.max_skipped_batches``) and one way to
write image grids.
"""

from __future__ import annotations

import logging
import random
from collections.abc import Mapping, Sequence
from typing import Any

import lightning as L
import numpy as np
import torch
from torch import Tensor

__all__ = ["BranchModule", "NonFiniteLossError", "image_grid", "get_rng_states", "set_rng_states"]

log = logging.getLogger(__name__)

NONFINITE_POLICIES = ("stop", "skip")
#: Checkpoint key of the global random states (:func:`get_rng_states`), restored when training resumes.
RNG_KEY = "sdn3d_rng_states"


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


def get_rng_states() -> dict[str, Any]:
    """The global random states (torch, CUDA, NumPy, Python) as tensors, ints and lists: a checkpoint holding
    them loads with ``torch.load(weights_only=True)``."""
    kind, keys, pos, has_gauss, gauss = np.random.get_state()
    version, state, python_gauss = random.getstate()
    states: dict[str, Any] = {
        "torch": torch.get_rng_state(),
        "numpy": {"kind": str(kind), "keys": torch.from_numpy(np.asarray(keys, dtype=np.int64)), "pos": int(pos),
                  "has_gauss": int(has_gauss), "gauss": float(gauss)},
        "python": {"version": int(version), "state": [int(v) for v in state], "gauss": python_gauss},
    }
    if torch.cuda.is_available() and torch.cuda.is_initialized():
        states["cuda"] = torch.cuda.get_rng_state_all()
    return states


def set_rng_states(states: Mapping[str, Any]) -> None:
    """Put back what :func:`get_rng_states` returned (CUDA only where there are as many devices)."""
    torch.set_rng_state(states["torch"])
    n = states["numpy"]
    np.random.set_state((n["kind"], n["keys"].numpy().astype(np.uint32), n["pos"], n["has_gauss"], n["gauss"]))
    p = states["python"]
    random.setstate((p["version"], tuple(p["state"]), p["gauss"]))
    cuda = states.get("cuda")
    if cuda and torch.cuda.is_available() and len(cuda) == torch.cuda.device_count():
        torch.cuda.set_rng_state_all(cuda)


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
        max_skipped_batches: under ``'skip'``, more consecutive dropped batches than this mean the run has
            diverged: it stops with :class:`NonFiniteLossError` (status ``failed``). ``fault.max_skipped_batches``;
            not a hyperparameter.

    A checkpoint also keeps the global random states; a run resumed from it puts them back when training
    starts, so with the datamodule's resumable sampler it trains on exactly what a straight run would.

    Attributes:
        nonfinite, max_skipped_batches: the policy above.
        skipped_batches: batches dropped by the ``'skip'`` policy so far.
        consecutive_skipped: of which the latest run of consecutive batches.
    """

    nonfinite: str = "stop"
    max_skipped_batches: int = 10

    def __init__(self, nonfinite: str = "stop", max_skipped_batches: int = 10) -> None:
        super().__init__()
        if int(max_skipped_batches) < 1:
            raise ValueError(f"fault.max_skipped_batches must be at least 1, got {max_skipped_batches!r}")
        self.nonfinite = nonfinite
        self.max_skipped_batches = int(max_skipped_batches)
        self.skipped_batches = 0
        self.consecutive_skipped = 0
        self._last_skipped: int | None = None
        self._buffers_before: list[tuple[Tensor, Tensor]] = []
        self._rng_states: Mapping[str, Any] | None = None

    # -- resuming: the random states go on where the checkpointed run left them ----------------------------------
    def on_save_checkpoint(self, checkpoint: dict[str, Any]) -> None:
        checkpoint[RNG_KEY] = get_rng_states()

    def on_load_checkpoint(self, checkpoint: dict[str, Any]) -> None:
        self._rng_states = checkpoint.get(RNG_KEY)

    def on_train_start(self) -> None:
        # After the sanity check (which a straight run did before epoch 0 only): the resumed run's next batch
        # draws the random numbers the checkpointed run's next batch would have drawn.
        if self._rng_states is not None:
            set_rng_states(self._rng_states)
            self._rng_states = None

    def on_train_batch_start(self, batch: Any, batch_idx: int) -> None:
        # Under skip, a dropped batch must leave no trace: its forward pass already moved BatchNorm's running
        # statistics (and other buffers) towards NaN, so they are put back (guard_loss). Buffers are small.
        if self.nonfinite == "skip":
            self._buffers_before = [(b, b.detach().clone()) for b in self.buffers()]

    @torch.no_grad()
    def _restore_buffers(self) -> None:
        for buffer, saved in self._buffers_before:
            buffer.copy_(saved)

    def _batch_number(self) -> int:
        """A number that grows by one per training batch (for "consecutive"): Lightning's batch count."""
        if self._trainer is not None:
            return int(self.trainer.fit_loop.epoch_loop.total_batch_idx)
        return self.skipped_batches if self._last_skipped is None else self._last_skipped + 1

    def guard_loss(self, loss: Tensor, name: str = "loss") -> bool:
        """True when ``loss`` is finite. Otherwise raise (policy stop) or count and return False (skip).

        Automatic optimisation: ``if not self.guard_loss(loss): return None`` skips the step.
        Manual optimisation: skip ``manual_backward``/``step`` when it returns False.
        A skipped batch's changes to the module's buffers (BatchNorm running statistics) are undone.
        Under skip, more than ``max_skipped_batches`` consecutive dropped batches raise :class:`NonFiniteLossError`.
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
        batch = self._batch_number()
        if batch != self._last_skipped:  # one batch may guard several losses: count it once
            self.skipped_batches += 1
            consecutive = self._last_skipped is not None and batch == self._last_skipped + 1
            self.consecutive_skipped = self.consecutive_skipped + 1 if consecutive else 1
            self._last_skipped = batch
        if self.consecutive_skipped > self.max_skipped_batches:
            raise NonFiniteLossError(
                f"non-finite training loss in {self.consecutive_skipped} consecutive batches, more than "
                f"fault.max_skipped_batches={self.max_skipped_batches} (latest: {where}): the run has diverged "
                "and stops; the last good checkpoint is kept. Lower the learning rate or check the data")
        self._restore_buffers()  # the batch's forward pass left its NaN in the running statistics
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
