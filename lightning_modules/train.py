"""The training run behind ``sdn3d-train``: config -> datamodule, module, trainer -> fit, test, summary.

Kept apart from the Hydra entry point (:mod:`sdn3d.cli.train`) so tests and notebooks can call
:func:`run_training` with a composed config. Hydra composes everything (branch, experiment, its recipe,
command-line overrides); :func:`run_training` runs the stages :func:`resolve_config`,
:func:`prepare_run_dir`, :func:`configure_process`, :func:`build_objects`, :func:`fit_and_test` and
:func:`write_summary`.
"""

from __future__ import annotations

import json
import logging
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import lightning as L
import torch
from hydra.utils import instantiate
from omegaconf import DictConfig, OmegaConf

from lightning_modules._base import NonFiniteLossError
from lightning_modules.checkpointing import AtomicCheckpointIO
from sdn3d.errors import UserInputError
from sdn3d.io import write_json_atomic, write_text_atomic

__all__ = ["TrainingError", "check_writable", "resolve_config", "resolve_resume", "run_training"]

log = logging.getLogger(__name__)

SAVED_CONFIG = "config.yaml"


class TrainingError(UserInputError, RuntimeError):
    """A run could not start or stopped for a reason the user can act on (message says which)."""


def _apply_command_line(target: DictConfig, overrides: list[str] | None) -> None:
    """Set the dotted ``key.sub=value`` command-line ``overrides`` on ``target``, in place.

    Only ``resume=`` needs this: a resumed run's config is its saved, resolved ``config.yaml``, which Hydra
    does not compose, so Hydra can not apply the command line to it. The values are read with Hydra's own
    override grammar, as Hydra reads them everywhere else: a multirun hands them over escaped
    (``trainer.max_time=00\\:01\\:00\\:00``), and plain YAML reads some strings differently (``1:30`` is a
    number to YAML 1.1). Group choices (``branch=...``), ``hydra.*`` keys and deletions are left out.
    """
    dotted = [o.lstrip("+") for o in (overrides or []) if "=" in o and "." in o.split("=", 1)[0]
              and not o.lstrip("+").startswith("hydra.") and not o.startswith("~")]
    if not dotted:
        return
    from hydra.core.override_parser.overrides_parser import OverridesParser

    for override in OverridesParser.create().parse_overrides(dotted):
        OmegaConf.update(target, override.key_or_group, override.value(), merge=False, force_add=True)


# (node, constructor argument, source): conf/train.yaml hands the fault policies to the module and datamodule.
_FAULT_LINKS = (("model", "nonfinite", "fault.nonfinite"), ("datamodule", "corrupt_sample", "fault.corrupt_sample"))


def resolve_resume(cfg: DictConfig, overrides: list[str] | None = None) -> DictConfig:
    """``resume=<run dir>``: the run's saved config, its ``last.ckpt``, plus dotted CLI overrides.

    Group choices (``branch=...``) can not change on resume; dotted overrides such as
    ``trainer.max_epochs=30`` apply (e.g. to train a finished run longer).
    """
    run = Path(str(cfg.resume)).expanduser()
    saved = run / SAVED_CONFIG
    if not saved.is_file():
        raise TrainingError(f"resume={str(run)!r}: no {SAVED_CONFIG} there; is it an sdn3d-train run directory?")
    ckpt = run / "checkpoints" / "last.ckpt"
    if not ckpt.is_file():
        raise TrainingError(f"resume={str(run)!r}: no checkpoints/last.ckpt to resume from")
    base = OmegaConf.load(saved)
    assert isinstance(base, DictConfig)
    # The saved config is resolved: link the fault policies to fault.* again, so that `fault.nonfinite=skip`
    # on resume reaches the module and datamodule (as conf/train.yaml does for a new run).
    for node, key, source in _FAULT_LINKS:
        if isinstance(base.get(node), DictConfig) and OmegaConf.select(base, source) is not None:
            base[node][key] = "${" + source + "}"
    _apply_command_line(base, overrides)
    base.resume = str(run)
    base.run_dir = str(run)
    base.ckpt_path = str(ckpt)
    return base


def check_writable(run_dir: Path) -> None:
    """Fail early, with the path, when the run directory can not be written."""
    try:
        run_dir.mkdir(parents=True, exist_ok=True)
        write_text_atomic(run_dir / ".write_probe", "ok\n")
        (run_dir / ".write_probe").unlink()
    except OSError as exc:
        raise TrainingError(f"output directory {str(run_dir)!r} is not writable: {exc.strerror or exc}") from exc


def _flat(cfg: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in cfg.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(_flat(value, name + "/"))
        elif isinstance(value, (list, tuple)):
            out[name] = str(list(value))
        elif value is None or isinstance(value, (bool, int, float, str)):
            out[name] = "None" if value is None else value
        else:
            out[name] = str(value)
    return out


def _scalars(metrics: Mapping[str, Any]) -> dict[str, float]:
    out = {}
    for key, value in metrics.items():
        if isinstance(value, torch.Tensor) and value.numel() == 1:
            value = value.item()
        if isinstance(value, (int, float)):
            out[str(key)] = float(value)
    return out


def _instantiate_group(group: Mapping[str, Any] | None) -> list[Any]:
    return [instantiate(v) for v in (group or {}).values() if v is not None and "_target_" in v]


def _append_summary(path: Path, record: Mapping[str, Any]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    line = json.dumps(record, sort_keys=True) + "\n"
    # One short O_APPEND write per run: concurrent multirun jobs never interleave within a line.
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    try:
        os.write(fd, line.encode("utf-8"))
    finally:
        os.close(fd)


def resolve_config(cfg: DictConfig, overrides: list[str] | None = None) -> DictConfig:
    """The run's config: ``cfg`` as Hydra composed it, or for ``resume=<run dir>`` that run's saved config
    with the dotted command-line ``overrides`` (:func:`resolve_resume`)."""
    return resolve_resume(cfg, overrides) if cfg.get("resume") else cfg


def prepare_run_dir(cfg: DictConfig) -> Path:
    """The run directory, checked writable; a new run saves its resolved config there (``config.yaml``)."""
    run_dir = Path(str(cfg.run_dir))
    check_writable(run_dir)
    if not cfg.get("resume"):
        write_text_atomic(run_dir / SAVED_CONFIG, OmegaConf.to_yaml(cfg, resolve=True))
    return run_dir


def configure_process(cfg: DictConfig) -> None:
    """torch threads, float32 matmul precision and the seeds of this process."""
    if cfg.get("torch_threads"):
        torch.set_num_threads(int(cfg.torch_threads))
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


def build_objects(cfg: DictConfig) -> RunObjects:
    """Datamodule, module, callbacks, loggers and trainer of the config (the config's hyperparameters logged)."""
    datamodule = instantiate(cfg.datamodule)
    model = instantiate(cfg.model)
    callbacks = _instantiate_group(cfg.get("callbacks"))
    loggers = _instantiate_group(cfg.get("logger"))
    if not loggers:  # LearningRateMonitor refuses to run without a logger; nothing to monitor into anyway
        callbacks = [c for c in callbacks if type(c).__name__ != "LearningRateMonitor"]
    if not cfg.trainer.get("enable_progress_bar", True):  # Lightning refuses a progress bar callback then
        callbacks = [c for c in callbacks if not isinstance(c, L.pytorch.callbacks.ProgressBar)]
    trainer: L.Trainer = instantiate(cfg.trainer, callbacks=callbacks, logger=loggers or False,
                                     plugins=[AtomicCheckpointIO()])
    params = _flat(OmegaConf.to_container(cfg, resolve=True))
    for logger in loggers:  # the run's whole config next to the module's own hyperparameters
        logger.log_hyperparams(params)
    return RunObjects(datamodule, model, trainer, loggers, params)


@dataclass
class FitResult:
    """How :func:`fit_and_test` went: ``status`` ok | failed (``error`` says why), the metrics, the best
    checkpoint, and when fitting started (``time.perf_counter``)."""

    status: str
    error: str | None
    metrics: dict[str, float]
    best: str | None
    started: float


def fit_and_test(cfg: DictConfig, run: RunObjects) -> FitResult:
    """Fit (from ``ckpt_path`` if set), then test the best checkpoint (``test_after_fit``).

    A non-finite loss under ``fault.nonfinite=stop`` ends the fit with status ``failed``, not an exception.
    """
    trainer, model, datamodule = run.trainer, run.model, run.datamodule
    ckpt_path = cfg.get("ckpt_path")
    if ckpt_path and not Path(str(ckpt_path)).is_file():
        raise TrainingError(f"ckpt_path={str(ckpt_path)!r} does not exist")
    started = time.perf_counter()
    status, error = "ok", None
    try:
        trainer.fit(model, datamodule=datamodule, ckpt_path=str(ckpt_path) if ckpt_path else None)
    except NonFiniteLossError as exc:
        status, error = "failed", str(exc)
    fit_metrics = _scalars(trainer.callback_metrics)
    test_metrics: dict[str, float] = {}
    checkpoint = trainer.checkpoint_callback
    best = getattr(checkpoint, "best_model_path", "") or None
    if status == "ok" and cfg.get("test_after_fit") and not trainer.fast_dev_run and not trainer.interrupted:
        results = trainer.test(model, datamodule=datamodule, ckpt_path=best if best else None)
        test_metrics = _scalars(results[0]) if results else {}
    if status == "ok":  # TensorBoard's HPARAMS tab: the run's config next to its final metrics
        for logger in run.loggers:
            if type(logger).__name__ == "TensorBoardLogger":
                logger.log_hyperparams(run.params, metrics={**fit_metrics, **test_metrics} or {"status_ok": 1.0})
    return FitResult(status, error, {**fit_metrics, **test_metrics}, best, started)


def _experiment_choice() -> str | None:
    """The ``experiment=`` of this Hydra run; None without one, or outside Hydra's main (a composed config)."""
    from hydra.core.hydra_config import HydraConfig

    if not HydraConfig.initialized():
        return None
    choice = HydraConfig.get().runtime.choices.get("experiment")
    return str(choice) if choice else None


def write_summary(cfg: DictConfig, run_dir: Path, run: RunObjects, result: FitResult,
                  overrides: list[str] | None = None) -> dict[str, Any]:
    """The run's summary: ``<run dir>/summary.json`` and one line of ``summary_file`` (global rank 0)."""
    trainer = run.trainer
    last = run_dir / "checkpoints" / "last.ckpt"
    summary = {
        "branch": str(cfg.branch_name),
        "ablation": str(cfg.ablation.name) if cfg.branch_name == "geometric" and cfg.get("ablation") else None,
        "experiment": _experiment_choice(),
        "run_dir": str(run_dir.resolve()),
        "best_ckpt": str(Path(result.best).resolve()) if result.best else None,
        "last_ckpt": str(last.resolve()) if last.is_file() else None,
        "metrics": result.metrics,
        "global_step": int(trainer.global_step),
        "epoch": int(trainer.current_epoch),
        "skipped_batches": int(getattr(run.model, "skipped_batches", 0)),
        "overrides": list(overrides or []),
        "seed": int(cfg.seed),
        "wall_s": round(time.perf_counter() - result.started, 3),
        "finished": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "status": result.status,
        "error": result.error,
    }
    if trainer.is_global_zero:
        write_json_atomic(run_dir / "summary.json", summary)
        if cfg.get("summary_file"):
            _append_summary(Path(str(cfg.summary_file)), summary)
    return summary


def run_training(cfg: DictConfig, overrides: list[str] | None = None) -> dict[str, Any]:
    """Train (and test) one branch as configured; returns the run summary (also written to disk).

    ``overrides`` are the command line's (Hydra's task overrides): recorded in the summary, and applied to a
    resumed run's saved config.

    Raises:
        TrainingError: bad resume target / checkpoint / unwritable output, or a non-finite loss under
            ``fault.nonfinite=stop`` (the last good checkpoint stays in ``<run>/checkpoints``).
    """
    cfg = resolve_config(cfg, overrides)
    run_dir = prepare_run_dir(cfg)
    configure_process(cfg)
    run = build_objects(cfg)
    result = fit_and_test(cfg, run)
    summary = write_summary(cfg, run_dir, run, result, overrides)
    if result.status != "ok":
        raise TrainingError(f"{result.error}\nrun directory: {run_dir}")
    return summary
