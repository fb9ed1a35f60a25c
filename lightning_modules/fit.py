"""The Lightning part of a training run: the run's objects from its config, fit and test.

:func:`lightning_modules.train.run_training` imports this module only once the checks before a run have passed, so a
refused ``sdn3d-train`` answers without importing Lightning (or torch, where the checks read no checkpoint).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import lightning as L
import torch
from hydra.utils import instantiate
from omegaconf import DictConfig, OmegaConf

from lightning_modules._base import NonFiniteLossError
from lightning_modules.callbacks import ThreadsLaterCallback
from lightning_modules.checkpointing import AtomicCheckpointIO, NonFiniteCheckpointError
from sdn3d.training.errors import error_file, error_sentence
from sdn3d.training.rundir import is_launcher
from sdn3d.training.start import StartPoint, threads_later
from sdn3d.training.summary import FitResult, Progress, flat_params, scalars

__all__ = ["RunObjects", "best_checkpoint", "build_objects", "configure_process", "fit_and_test", "run_progress"]

log = logging.getLogger(__name__)


def configure_process(cfg: DictConfig) -> None:
    """torch threads (``threads``), float32 matmul precision and the seeds of this process."""
    if cfg.get("threads") is not None:
        torch.set_num_threads(int(cfg.threads))
    if cfg.get("float32_matmul_precision"):
        torch.set_float32_matmul_precision(str(cfg.float32_matmul_precision))
    L.seed_everything(int(cfg.seed), workers=True)


@dataclass
class RunObjects:
    """What :func:`build_objects` makes from the config; ``params`` is the flattened resolved config."""

    datamodule: L.LightningDataModule
    model: L.LightningModule
    trainer: L.Trainer
    loggers: list[Any]
    params: dict[str, Any]


def _instantiate_group(group: Mapping[str, Any] | None) -> list[Any]:
    return [instantiate(v) for v in (group or {}).values() if v is not None and "_target_" in v]


def build_objects(cfg: DictConfig, start: StartPoint | None = None) -> RunObjects:
    """Datamodule, module, callbacks, loggers and trainer of the config (the config's hyperparameters logged).

    For ``resume=`` of a run trained elsewhere (copied or moved), the checkpoint callbacks' recorded paths are read
    as paths of this run directory (``start.checkpoint_dirs``, :class:`AtomicCheckpointIO`'s ``relocate``)."""
    datamodule = instantiate(cfg.datamodule)
    model = instantiate(cfg.model)
    callbacks = _instantiate_group(cfg.get("callbacks"))
    later = threads_later(cfg)
    if later is not None:
        callbacks.append(ThreadsLaterCallback(later))
    loggers = _instantiate_group(cfg.get("logger"))
    if not loggers:  # LearningRateMonitor refuses to run without a logger; nothing to monitor into anyway
        callbacks = [c for c in callbacks if type(c).__name__ != "LearningRateMonitor"]
    if not cfg.trainer.get("enable_progress_bar", True):  # Lightning refuses a progress bar callback then
        callbacks = [c for c in callbacks if not isinstance(c, L.pytorch.callbacks.ProgressBar)]
    relocate = {}
    if cfg.get("resume") and start is not None:
        for callback in callbacks:
            old = start.checkpoint_dirs.get(getattr(callback, "state_key", ""))
            if isinstance(callback, L.pytorch.callbacks.ModelCheckpoint) and old and old != callback.dirpath:
                relocate[old] = str(callback.dirpath)
    if relocate:
        log.info("resuming a run trained elsewhere: its checkpoint paths %s are read as %s", sorted(relocate),
                 sorted(relocate.values()))
    trainer: L.Trainer = instantiate(cfg.trainer, callbacks=callbacks, logger=loggers or False,
                                     plugins=[AtomicCheckpointIO(relocate)])
    params = flat_params(OmegaConf.to_container(cfg, resolve=True))
    for logger in loggers:  # the run's whole config next to the module's own hyperparameters
        logger.log_hyperparams(params)
    return RunObjects(datamodule, model, trainer, loggers, params)


def fit_and_test(cfg: DictConfig, run: RunObjects) -> FitResult:
    """Fit (from ``ckpt_path`` if set), then test the best checkpoint (``test_after_fit``).

    The best checkpoint is the one the branch's ``monitor`` picks on the *validation* part (the split rules
    carve it from the training frames; :mod:`sdn3d.data.splits`): ``tested`` is ``'best'`` then, ``'final'``
    when no checkpoint was selected (the weights at the end of fitting), None when nothing was tested.

    A non-finite loss under ``fault.nonfinite=stop`` (or too many under ``skip``), or weights that became
    non-finite (no checkpoint is written then), end the fit with status ``failed``, not an exception.
    """
    trainer, model, datamodule = run.trainer, run.model, run.datamodule
    ckpt_path = cfg.get("ckpt_path")  # checked by check_start before the run started
    started = time.perf_counter()
    status, error, where = "ok", None, None
    try:
        trainer.fit(model, datamodule=datamodule, ckpt_path=str(ckpt_path) if ckpt_path else None)
    except (NonFiniteLossError, NonFiniteCheckpointError) as exc:
        status, error, where = "failed", error_sentence(exc), error_file(exc)
    fit_metrics = scalars(trainer.callback_metrics)
    test_metrics: dict[str, float] = {}
    best = best_checkpoint(run)
    tested = None
    if status == "ok" and cfg.get("test_after_fit") and not trainer.fast_dev_run and not trainer.interrupted:
        results = trainer.test(model, datamodule=datamodule, ckpt_path=best if best else None)
        test_metrics = scalars(results[0]) if results else {}
        tested = "best" if best else "final"
    if status == "ok":  # TensorBoard's HPARAMS tab: the run's config next to its final metrics
        for logger in run.loggers:
            if type(logger).__name__ == "TensorBoardLogger":
                logger.log_hyperparams(run.params, metrics={**fit_metrics, **test_metrics} or {"status_ok": 1.0})
    return FitResult(status, error, {**fit_metrics, **test_metrics}, best, started, where, tested)


def best_checkpoint(run: RunObjects | None) -> str | None:
    """The best checkpoint the run's checkpoint callback has selected so far; None: none (or no run)."""
    if run is None:
        return None
    return getattr(run.trainer.checkpoint_callback, "best_model_path", "") or None


def run_progress(run: RunObjects | None) -> Progress:
    """What the run's objects got to, for its summary (:class:`sdn3d.training.summary.Progress`); ``run`` None: the
    run failed before its objects were built."""
    if run is None:
        return Progress(writer=is_launcher())
    skipped = run.datamodule.skip_summary() if hasattr(run.datamodule, "skip_summary") else {}
    return Progress(int(run.trainer.global_step), int(run.trainer.current_epoch),
                    int(getattr(run.model, "skipped_batches", 0)), dict(skipped), bool(run.trainer.is_global_zero))
