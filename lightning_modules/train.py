"""The training run behind ``sdn3d-train``: config -> datamodule, module, trainer -> fit, test, summary.

Kept apart from the Hydra entry point (:mod:`sdn3d.cli.train`) so tests and notebooks can call
:func:`run_training` with a composed config.
"""

from __future__ import annotations

import json
import logging
import os
import time
from collections.abc import Mapping
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

__all__ = ["TrainingError", "apply_preset", "resolve_resume", "run_training", "check_writable"]

log = logging.getLogger(__name__)

SAVED_CONFIG = "config.yaml"


class TrainingError(UserInputError, RuntimeError):
    """A run could not start or stopped for a reason the user can act on (message says which)."""


def _dotted(overrides: list[str] | None) -> list[str]:
    """The ``key.sub=value`` command-line overrides (not group choices, not hydra.*, not deletions)."""
    return [o.lstrip("+") for o in (overrides or []) if "=" in o and "." in o.split("=", 1)[0]
            and not o.lstrip("+").startswith("hydra.") and not o.startswith("~")]


def _reapply(target: DictConfig, overrides: list[str] | None) -> DictConfig:
    """``target`` with the dotted command-line ``overrides`` set again, their values read by Hydra's own
    override grammar: a multirun hands them over escaped (``trainer.max_time=00\\:01\\:00\\:00``), and
    plain YAML reads some strings differently (``1:30`` is a number to YAML 1.1)."""
    dotted = _dotted(overrides)
    if not dotted:
        return target
    from hydra.core.override_parser.overrides_parser import OverridesParser

    for override in OverridesParser.create().parse_overrides(dotted):
        value = override.value()
        OmegaConf.update(target, override.key_or_group, value, merge=False, force_add=True)
    return target


def apply_preset(cfg: DictConfig, overrides: list[str] | None = None) -> DictConfig:
    """Merge ``cfg.presets[cfg.preset]`` (a branch's demo / paper budget) over the root config.

    Dotted command-line ``overrides`` are applied again afterwards: what the user typed beats the preset.
    """
    name = cfg.get("preset")
    if not name:
        return cfg
    presets = cfg.get("presets") or {}
    if name not in presets:
        raise TrainingError(f"preset {name!r} is not defined for branch {cfg.get('branch_name')!r}; "
                            f"it has {sorted(presets)} (conf/branch/{cfg.get('branch_name')}.yaml, key presets)")
    merged = _reapply(OmegaConf.merge(cfg, presets[name]), overrides)
    assert isinstance(merged, DictConfig)
    return merged


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
    base = _reapply(base, overrides)
    base.resume = str(run)
    base.run_dir = str(run)
    base.ckpt_path = str(ckpt)
    assert isinstance(base, DictConfig)
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


def run_training(cfg: DictConfig, overrides: list[str] | None = None) -> dict[str, Any]:
    """Train (and test) one branch as configured; returns the run summary (also written to disk).

    Raises:
        TrainingError: bad preset / resume target / unwritable output, or a non-finite loss under
            ``fault.nonfinite=stop`` (the last good checkpoint stays in ``<run>/checkpoints``).
    """
    if cfg.get("resume"):
        cfg = resolve_resume(cfg, overrides)
    else:
        cfg = apply_preset(cfg, overrides)
    run_dir = Path(str(cfg.run_dir))
    check_writable(run_dir)
    if not cfg.get("resume"):
        write_text_atomic(run_dir / SAVED_CONFIG, OmegaConf.to_yaml(cfg, resolve=True))
    if cfg.get("torch_threads"):
        torch.set_num_threads(int(cfg.torch_threads))
    if cfg.get("float32_matmul_precision"):
        torch.set_float32_matmul_precision(str(cfg.float32_matmul_precision))
    L.seed_everything(int(cfg.seed), workers=True)

    datamodule = instantiate(cfg.datamodule)
    if hasattr(datamodule, "corrupt_sample"):
        datamodule.corrupt_sample = str(cfg.fault.corrupt_sample)
    model = instantiate(cfg.model)
    model.nonfinite = str(cfg.fault.nonfinite)
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
    last = run_dir / "checkpoints" / "last.ckpt"
    if status == "ok":  # TensorBoard's HPARAMS tab: the run's config next to its final metrics
        for logger in loggers:
            if type(logger).__name__ == "TensorBoardLogger":
                logger.log_hyperparams(params, metrics={**fit_metrics, **test_metrics} or {"status_ok": 1.0})
    summary = {
        "branch": str(cfg.branch_name),
        "ablation": str(cfg.ablation.name) if cfg.branch_name == "geometric" and cfg.get("ablation") else None,
        "preset": cfg.get("preset"),
        "run_dir": str(run_dir.resolve()),
        "best_ckpt": str(Path(best).resolve()) if best else None,
        "last_ckpt": str(last.resolve()) if last.is_file() else None,
        "metrics": {**fit_metrics, **test_metrics},
        "global_step": int(trainer.global_step),
        "epoch": int(trainer.current_epoch),
        "skipped_batches": int(getattr(model, "skipped_batches", 0)),
        "overrides": list(overrides or []),
        "seed": int(cfg.seed),
        "wall_s": round(time.perf_counter() - started, 3),
        "finished": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "status": status,
        "error": error,
    }
    if trainer.is_global_zero:
        write_json_atomic(run_dir / "summary.json", summary)
        if cfg.get("summary_file"):
            _append_summary(Path(str(cfg.summary_file)), summary)
    if status != "ok":
        raise TrainingError(f"{error}\nrun directory: {run_dir}")
    return summary
