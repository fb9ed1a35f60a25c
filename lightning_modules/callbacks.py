"""Small training callbacks shared by every branch."""

from __future__ import annotations

import logging
import time

import lightning as L
import torch

from sdn3d.training.start import ThreadsLater

__all__ = ["EpochLog", "ThreadsLaterCallback"]

log = logging.getLogger("sdn3d.train")
_PER_CLASS = ("/iou_", "/pq_", "/sq_", "/rq_", "/template_prob")  # one per class: too many for a line


class EpochLog(L.Callback):
    """One line per training epoch in the run's log (``train.log``): epoch, steps, seconds and the epoch's
    logged metrics. Without a progress bar (``trainer.enable_progress_bar=false``, runs in the background
    or ``sdn3d-demo train.parallel=true``) it is how a user sees how far a run has got.

    Args:
        keys: metric name prefixes to print, in this order (default: the training losses, then the validation
            metrics).
        max_metrics: at most this many metrics of each prefix per line (a joint stage's dozen training terms once
            pushed every validation figure off the line).
    """

    def __init__(self, keys: tuple[str, ...] = ("train/", "val/"), max_metrics: int = 12) -> None:
        self.keys = tuple(keys)
        self.max_metrics = int(max_metrics)
        self._started = time.perf_counter()
        self._validated_epoch = -1

    def on_train_epoch_start(self, trainer: L.Trainer, pl_module: L.LightningModule) -> None:
        self._started = time.perf_counter()

    def on_validation_epoch_end(self, trainer: L.Trainer, pl_module: L.LightningModule) -> None:
        if not trainer.sanity_checking:
            self._validated_epoch = trainer.current_epoch

    def on_train_epoch_end(self, trainer: L.Trainer, pl_module: L.LightningModule) -> None:
        if trainer.sanity_checking or not trainer.is_global_zero:
            return
        # callback_metrics keeps the last validation's values through epochs without validation
        # (check_val_every_n_epoch > 1): print val/ only for an epoch that validated.
        stale = "val/" if self._validated_epoch != trainer.current_epoch else None
        shown: dict[str, list[str]] = {key: [] for key in self.keys}
        for name, value in sorted(trainer.callback_metrics.items()):
            if stale is not None and name.startswith(stale):
                continue
            key = next((k for k in self.keys if name.startswith(k)), None)
            if (key is not None and not name.endswith(("_step", "_epoch")) and not any(
                    part in name for part in _PER_CLASS) and torch.is_tensor(value) and value.numel() == 1):
                shown[key].append(f"{name} {float(value):.4g}")
        metrics = [text for key in self.keys for text in shown[key][: self.max_metrics]]
        total = trainer.max_epochs if trainer.max_epochs and trainer.max_epochs > 0 else "?"
        log.info("epoch %d/%s done: step %d, %.1f s%s", trainer.current_epoch + 1, total, trainer.global_step,
                 time.perf_counter() - self._started, ("; " + ", ".join(metrics)) if metrics else "")


class ThreadsLaterCallback(L.Callback):
    """``threads_later`` (:class:`sdn3d.training.start.ThreadsLater`): ``threads`` torch threads from the training
    epoch after the first ``after_epochs`` on (a resumed run past it: from its first epoch). By epoch, never by
    timing: a run's arithmetic depends on its thread count, and so stays the same whatever else the machine does."""

    def __init__(self, later: ThreadsLater) -> None:
        self.later = later

    def on_train_epoch_start(self, trainer: L.Trainer, pl_module: L.LightningModule) -> None:
        if trainer.current_epoch >= self.later.after_epochs and torch.get_num_threads() != self.later.threads:
            torch.set_num_threads(self.later.threads)
            log.info("epoch %d: %d torch threads from here on (threads_later)", trainer.current_epoch + 1,
                     self.later.threads)
