"""The training run behind ``sdn3d-train``: config -> checks -> datamodule, module, trainer -> fit, test, summary.

Kept apart from the Hydra entry point (:mod:`sdn3d.cli.train`) so tests and notebooks can call
:func:`run_training` with a composed config. Hydra composes everything (branch, experiment, its recipe,
command-line overrides); :func:`run_training` composes the stages: the run's config and the checks before anything
is written (:mod:`sdn3d.training.resume`, :mod:`sdn3d.training.start`), the run directory and its lock
(:mod:`sdn3d.training.rundir`, :mod:`sdn3d.training.locks`), the objects, fit and test
(:mod:`lightning_modules.fit`), and the summary (:mod:`sdn3d.training.summary`).

This module imports neither Lightning nor torch: run management lives in :mod:`sdn3d.training`, which does not
import Lightning, and :mod:`lightning_modules.fit`, the part that does, is imported only once every check has
passed. A refused run (a bad ``ckpt_path=`` or override, a run directory that holds a run, an unwritable output)
answers in about a second instead of after Lightning's ten-second import.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from omegaconf import DictConfig

from sdn3d.training.errors import RunFailedError, error_file, error_sentence
from sdn3d.training.locks import run_lock
from sdn3d.training.resume import finished_resume, resolve_config
from sdn3d.training.rundir import check_new_run_dir, check_writable, prepare_run_dir
from sdn3d.training.start import check_overrides, check_start, check_threads
from sdn3d.training.summary import Before, FitResult, export_for_inference, record_failure, scalars, write_summary

if TYPE_CHECKING:
    from lightning_modules.fit import RunObjects

__all__ = ["run_training"]

log = logging.getLogger(__name__)


def run_training(cfg: DictConfig, overrides: list[str] | None = None) -> dict[str, Any]:
    """Train (and test) one branch as configured; returns the run summary (also written to disk).

    ``overrides`` are the command line's (Hydra's task overrides): recorded in the summary, and applied to a
    resumed run's saved config (:func:`sdn3d.training.resume.resolve_resume`). Before anything is written, the
    checkpoint training continues from is checked (:func:`sdn3d.training.start.check_start`). Once the run directory
    and ``summary_file`` are found writable, whatever stops the run is recorded (status ``failed``, ``error``,
    ``error_file``; a resume that failed before writing a checkpoint leaves ``summary.json`` as it was:
    :func:`sdn3d.training.summary.write_summary`) and then raised. Lightning is imported after these checks.

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
        # Lightning (about ten seconds to import) only for a run that passed every check
        from lightning_modules.fit import best_checkpoint, build_objects, configure_process, fit_and_test, run_progress

        run_dir = prepare_run_dir(cfg)
        started = time.perf_counter()
        run: RunObjects | None = None
        try:
            configure_process(cfg)
            run = build_objects(cfg, start)
            result = fit_and_test(cfg, run)
        except Exception as exc:
            failed = FitResult("failed", error_sentence(exc), scalars(run.trainer.callback_metrics) if run else {},
                               best_checkpoint(run), started, error_file(exc))
            record_failure(cfg, run_dir, run_progress(run), failed, overrides, before)
            raise
        summary = write_summary(cfg, run_dir, run_progress(run), result, overrides, before)
        if result.status != "ok":
            raise RunFailedError(f"{result.error} (run directory: {run_dir})")
        if run_progress(run).writer:
            export_for_inference(run_dir)
        return summary
