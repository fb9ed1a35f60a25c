"""What each attempt on a run directory records, whatever stopped it: ``<run dir>/summary.json``, one line of
``<run dir>/summary_log.jsonl`` and one of ``summary_file``.

Every attempt that starts (once its run directory and ``summary_file`` are found writable) records its summary
whatever stops it: ``status`` ok / failed, ``error`` (one sentence), ``error_file`` (the file at fault, when known)
and what the fault policies skipped, as one line of ``<run dir>/summary_log.jsonl`` and of ``summary_file``, and as
``<run dir>/summary.json`` unless it is a resume that failed before writing a checkpoint (the run's figures stay
those of the attempt that made its checkpoints). Mistakes found before the start write nothing.
"""

from __future__ import annotations

import json
import logging
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from omegaconf import DictConfig

from sdn3d.errors import UserInputError
from sdn3d.io import write_json_atomic

__all__ = ["SUMMARY_LOG", "Before", "FitResult", "Progress", "export_for_inference", "flat_params", "record_failure",
           "scalars", "write_summary"]

log = logging.getLogger(__name__)

#: Every attempt on a run directory (a new run, each resume), ok or failed, appends its summary here.
SUMMARY_LOG = "summary_log.jsonl"


@dataclass
class FitResult:
    """How fitting went: ``status`` ok | failed (``error`` says why, ``error_file`` names the file at fault when
    known), the metrics, the best checkpoint, when fitting started (``time.perf_counter``), and which weights the
    test figures come from (``tested``: ``'best'``, ``'final'`` or None, see
    :func:`lightning_modules.fit.fit_and_test`)."""

    status: str
    error: str | None
    metrics: dict[str, float]
    best: str | None
    started: float
    error_file: str | None = None
    tested: str | None = None


@dataclass
class Progress:
    """What an attempt's trainer, module and datamodule got to, for its summary (the defaults: nothing was built).

    ``skipped``: what the corrupt-sample policy left out (``skipped_samples`` / ``skipped_fraction`` /
    ``skipped_files``, :meth:`datamodules._base.BranchDataModule.skip_summary`); ``writer``: whether this process
    writes the run's files (the trainer's global rank 0, or before there is a trainer, the launching process)."""

    global_step: int = 0
    epoch: int = 0
    skipped_batches: int = 0
    skipped: dict[str, Any] = field(default_factory=dict)
    writer: bool = True


@dataclass
class Before:
    """What a run directory held when an attempt started: its summary (a resume's earlier one; None: none or
    unreadable), its checkpoints (name -> size and modification time), and for a resume the command its first
    attempt was started with (``{"overrides": [...], "experiment": name or None}``, from the ``.hydra/`` record
    :func:`sdn3d.training.rundir.save_hydra_record` saved; None: no record). A run killed before it wrote its
    summary (a machine's time limit during the test) keeps its experiment and command line through that record."""

    summary: dict[str, Any] | None
    checkpoints: dict[str, tuple[int, int]]
    command: dict[str, Any] | None = None

    @classmethod
    def of(cls, cfg: DictConfig, run_dir: Path) -> Before:
        summary = command = None
        if cfg.get("resume"):
            try:
                loaded = json.loads((run_dir / "summary.json").read_text(encoding="utf-8"))
                summary = loaded if isinstance(loaded, dict) else None
            except (OSError, UnicodeDecodeError, ValueError):
                summary = None
            command = _first_command(run_dir)
        return cls(summary, _checkpoint_files(run_dir), command)


def _first_command(run_dir: Path) -> dict[str, Any] | None:
    """The overrides and ``experiment=`` choice a run was started with, from its ``.hydra/overrides.yaml`` and
    ``.hydra/hydra.yaml``; None when either is missing or unreadable."""
    from omegaconf import OmegaConf
    from omegaconf.errors import OmegaConfBaseException

    try:
        overrides = OmegaConf.to_container(OmegaConf.load(run_dir / ".hydra" / "overrides.yaml"))
        experiment = OmegaConf.select(OmegaConf.load(run_dir / ".hydra" / "hydra.yaml"),
                                      "hydra.runtime.choices.experiment", default=None)
    except (OSError, ValueError, OmegaConfBaseException):
        return None
    if not isinstance(overrides, list):
        return None
    return {"overrides": [str(o) for o in overrides], "experiment": str(experiment) if experiment else None}


def _checkpoint_files(run_dir: Path) -> dict[str, tuple[int, int]]:
    folder = run_dir / "checkpoints"
    if not folder.is_dir():
        return {}
    return {p.name: (p.stat().st_size, p.stat().st_mtime_ns) for p in folder.iterdir() if p.suffix == ".ckpt"}


def _experiment_choice() -> str | None:
    """The ``experiment=`` of this Hydra run; None without one, or outside Hydra's main (a composed config)."""
    from hydra.core.hydra_config import HydraConfig

    if not HydraConfig.initialized():
        return None
    choice = HydraConfig.get().runtime.choices.get("experiment")
    return str(choice) if choice else None


def write_summary(cfg: DictConfig, run_dir: Path, progress: Progress, result: FitResult,
                  overrides: list[str] | None = None, before: Before | None = None) -> dict[str, Any]:
    """The attempt's summary: ``<run dir>/summary.json``, one line of ``<run dir>/summary_log.jsonl`` and one of
    ``summary_file`` (written by the process that writes the run's files, ``progress.writer``).

    A resume (``before`` holds the run's earlier summary) that failed without writing a checkpoint leaves
    ``summary.json`` as it was: its failure goes to the two logs only, and the run's figures stay those of the
    attempt that made its checkpoints. A resumed run's summary keeps the ``experiment`` and ``overrides`` the run
    was started with (its earlier summary's, else its ``.hydra/`` record's: :class:`Before`); ``resume_overrides``
    is the command line of the resume (None: never resumed). ``monitor`` is the validation figure that selects the
    checkpoint, of the run's own config (a resume's saved one).

    ``skipped_batches`` counts batches the non-finite policy dropped; ``skipped_samples`` / ``skipped_fraction`` /
    ``skipped_files`` what the corrupt-sample policy left out (:class:`Progress`).
    """
    last = run_dir / "checkpoints" / "last.ckpt"
    skipped = {"skipped_samples": 0, "skipped_fraction": 0.0, "skipped_files": []}
    skipped.update(progress.skipped)
    branch = cfg.get("branch_name")
    earlier = before.summary if before is not None and before.summary is not None else None
    first = earlier if earlier is not None else before.command if before is not None else None
    resumed = bool(cfg.get("resume"))
    started_with = first.get("overrides") if first is not None else None
    summary = {
        "branch": str(branch) if branch is not None else None,
        "ablation": str(cfg.ablation.name) if branch == "geometric" and cfg.get("ablation") else None,
        "experiment": first.get("experiment") if first is not None else _experiment_choice(),
        "variant": str(cfg.variant) if cfg.get("variant") is not None else None,
        "run_dir": str(run_dir.resolve()),
        "best_ckpt": str(Path(result.best).resolve()) if result.best else None,
        "last_ckpt": str(last.resolve()) if last.is_file() else None,
        "metrics": result.metrics,
        # Which weights the test/ metrics come from: 'best' = best_ckpt, selected by `selected_by` on the
        # validation part (never on test); 'final' = the weights at the end of fitting; None = not tested.
        "tested_checkpoint": result.tested,
        "monitor": str(cfg.monitor) if cfg.get("monitor") else None,
        "selected_by": (f"{cfg.monitor} ({cfg.get('monitor_mode', 'min')}) on the validation part"
                        if cfg.get("monitor") else None),
        "global_step": int(progress.global_step),
        "epoch": int(progress.epoch),
        "skipped_batches": int(progress.skipped_batches),
        **skipped,
        "overrides": list(started_with if isinstance(started_with, list) else [] if resumed else overrides or []),
        "resume_overrides": list(overrides or []) if resumed else None,
        "seed": int(cfg.seed),
        "wall_s": round(time.perf_counter() - result.started, 3),
        "finished": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "status": result.status,
        "error": result.error,
        "error_file": result.error_file,
    }
    keep = earlier is not None and result.status != "ok" and _checkpoint_files(run_dir) == before.checkpoints
    if progress.writer:
        if keep:
            log.error("the resumed run failed before it wrote a checkpoint: %s keeps the run's earlier summary "
                      "(status %s); this attempt is recorded in %s", run_dir / "summary.json", earlier.get("status"),
                      run_dir / SUMMARY_LOG)
        else:
            write_json_atomic(run_dir / "summary.json", summary)
        _append_summary(run_dir / SUMMARY_LOG, summary)
        if cfg.get("summary_file"):
            _append_summary(Path(str(cfg.summary_file)), summary)
    return summary


def record_failure(cfg: DictConfig, run_dir: Path, progress: Progress, result: FitResult,
                   overrides: list[str] | None, before: Before | None = None) -> None:
    """Write the summary of a run stopped by an error (``result``, status failed) as :func:`write_summary` does,
    best effort: a full disk may refuse it too, and the run's own error is the one to raise."""
    try:
        write_summary(cfg, run_dir, progress, result, overrides, before)
    except Exception as write_error:  # noqa: BLE001 - the run's own error is the one to raise
        log.error("could not record the failed run's summary in %s: %s", run_dir, write_error)


def _append_summary(path: Path, record: Mapping[str, Any]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    line = json.dumps(record, sort_keys=True) + "\n"
    # One short O_APPEND write per run: concurrent multirun jobs never interleave within a line.
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    try:
        os.write(fd, line.encode("utf-8"))
    finally:
        os.close(fd)


def export_for_inference(run_dir: Path) -> None:
    """``checkpoints/inference.pt`` of a run that ended ok: what ``sdn3d-edit run=`` loads instead of the checkpoint
    (:func:`sdn3d.runs.export_run_checkpoint`); a failure is a warning (``run=`` then loads the checkpoint)."""
    from sdn3d.runs import export_run_checkpoint

    try:
        log.info("inference export: %s", export_run_checkpoint(run_dir / "summary.json"))
    except (UserInputError, OSError) as exc:
        log.warning("no inference export written (%s); run= loads the checkpoint", exc)


def flat_params(cfg: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """A resolved config tree as the loggers' flat hyper-parameters (``a/b/c``: plain values, lists as text)."""
    out: dict[str, Any] = {}
    for key, value in cfg.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(flat_params(value, name + "/"))
        elif isinstance(value, (list, tuple)):
            out[name] = str(list(value))
        elif value is None or isinstance(value, (bool, int, float, str)):
            out[name] = "None" if value is None else value
        else:
            out[name] = str(value)
    return out


def scalars(metrics: Mapping[str, Any]) -> dict[str, float]:
    """The one-number entries of ``metrics`` (tensors of one element, ints, floats) as floats."""
    import torch  # here, not at the top: the checks before a run import this module and need no torch

    out = {}
    for key, value in metrics.items():
        if isinstance(value, torch.Tensor) and value.numel() == 1:
            value = value.item()
        if isinstance(value, (int, float)):
            out[str(key)] = float(value)
    return out
