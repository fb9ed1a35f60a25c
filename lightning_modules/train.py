"""The training run behind ``sdn3d-train``: config -> datamodule, module, trainer -> fit, test, summary.

Kept apart from the Hydra entry point (:mod:`sdn3d.cli.train`) so tests and notebooks can call
:func:`run_training` with a composed config. Hydra composes everything (branch, experiment, its recipe,
command-line overrides); :func:`run_training` composes the stages: the run's config and the checks before anything
is written (:mod:`sdn3d.training.resume`, :mod:`sdn3d.training.start`), the run directory and its lock
(:mod:`sdn3d.training.rundir`, :mod:`sdn3d.training.locks`), the objects (:func:`build_objects`), fit and test
(:func:`fit_and_test`), and the summary (:mod:`sdn3d.training.summary`). Run management lives in
:mod:`sdn3d.training`, which does not import Lightning; this module is the part that does.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import lightning as L
import torch
from hydra.utils import instantiate
from omegaconf import DictConfig, OmegaConf

from lightning_modules._base import NonFiniteLossError
from lightning_modules.checkpointing import AtomicCheckpointIO, NonFiniteCheckpointError
from sdn3d.training.errors import RunFailedError, error_file, error_sentence
from sdn3d.training.locks import run_lock
from sdn3d.training.resume import finished_resume, resolve_config
from sdn3d.training.rundir import check_new_run_dir, check_writable, is_launcher, prepare_run_dir
from sdn3d.training.start import StartPoint, check_overrides, check_start, check_threads
from sdn3d.training.summary import (
    Before,
    FitResult,
    Progress,
    export_for_inference,
    flat_params,
    record_failure,
    scalars,
    write_summary,
)

__all__ = ["RunObjects", "build_objects", "configure_process", "fit_and_test", "run_training"]

log = logging.getLogger(__name__)


def run_training(cfg: DictConfig, overrides: list[str] | None = None) -> dict[str, Any]:
    """Train (and test) one branch as configured; returns the run summary (also written to disk).

    ``overrides`` are the command line's (Hydra's task overrides): recorded in the summary, and applied to a
    resumed run's saved config (:func:`sdn3d.training.resume.resolve_resume`). Before anything is written, the
    checkpoint training continues from is checked (:func:`sdn3d.training.start.check_start`). Once the run directory
    and ``summary_file`` are found writable, whatever stops the run is recorded (status ``failed``, ``error``,
    ``error_file``; a resume that failed before writing a checkpoint leaves ``summary.json`` as it was:
    :func:`sdn3d.training.summary.write_summary`) and then raised.

    A resume of a run that has trained its whole budget and whose summary says ok does nothing: it logs so and
    returns that summary, changing no file.

    Raises:
        TrainingError: bad resume target / override (``+max_epochs=2``) / checkpoint (an export, another branch's, a
            budget below what it trained) / ``threads`` not null or a positive integer / a new run into a directory
            that holds a run (without ``overwrite=true``) / unwritable output (before the run starts).
        RunFailedError: the run ended with status ``failed``: a non-finite loss under ``fault.nonfinite=stop``
            or too many under ``skip``, or non-finite weights (the last good checkpoint stays in
            ``<run>/checkpoints``).
        Any other error of the run (a corrupt sample, a full disk, a bug), after recording it.
    """
    cfg = resolve_config(cfg, overrides)
    check_overrides(cfg, overrides)
    check_threads(cfg)
    start = check_start(cfg)
    check_new_run_dir(cfg)
    run_dir = Path(str(cfg.run_dir))
    check_writable(run_dir)
    with run_lock(run_dir):
        before = Before.of(cfg, run_dir)
        finished = finished_resume(cfg, start, before.summary)
        if finished is not None:
            return dict(finished)
        run_dir = prepare_run_dir(cfg)
        started = time.perf_counter()
        run: RunObjects | None = None
        try:
            configure_process(cfg)
            run = build_objects(cfg, start)
            result = fit_and_test(cfg, run)
        except Exception as exc:
            failed = FitResult("failed", error_sentence(exc), scalars(run.trainer.callback_metrics) if run else {},
                               _best(run), started, error_file(exc))
            record_failure(cfg, run_dir, _progress(run), failed, overrides, before)
            raise
        summary = write_summary(cfg, run_dir, _progress(run), result, overrides, before)
        if result.status != "ok":
            raise RunFailedError(f"{result.error} (run directory: {run_dir})")
        if _progress(run).writer:
            export_for_inference(run_dir)
        return summary


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
    best = _best(run)
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


def _best(run: RunObjects | None) -> str | None:
    """The best checkpoint the run's checkpoint callback has selected so far; None: none (or no run)."""
    if run is None:
        return None
    return getattr(run.trainer.checkpoint_callback, "best_model_path", "") or None


def _progress(run: RunObjects | None) -> Progress:
    """What the run's objects got to, for its summary (:class:`sdn3d.training.summary.Progress`); ``run`` None: the
    run failed before its objects were built."""
    if run is None:
        return Progress(writer=is_launcher())
    skipped = run.datamodule.skip_summary() if hasattr(run.datamodule, "skip_summary") else {}
    return Progress(int(run.trainer.global_step), int(run.trainer.current_epoch),
                    int(getattr(run.model, "skipped_batches", 0)), dict(skipped), bool(run.trainer.is_global_zero))
