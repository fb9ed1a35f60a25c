"""The training run behind ``sdn3d-train``: config -> datamodule, module, trainer -> fit, test, summary.

Kept apart from the Hydra entry point (:mod:`sdn3d.cli.train`) so tests and notebooks can call
:func:`run_training` with a composed config. Hydra composes everything (branch, experiment, its recipe,
command-line overrides); :func:`run_training` runs the stages :func:`resolve_config`,
:func:`prepare_run_dir`, :func:`configure_process`, :func:`build_objects`, :func:`fit_and_test` and
:func:`write_summary`.

Every run that starts (once its run directory and ``summary_file`` are found writable) writes its summary,
``<run dir>/summary.json`` and one ``summary_file`` line, whatever stops it: ``status`` ok / failed,
``error`` (one sentence), ``error_file`` (the file at fault, when known) and what the fault policies
skipped. A resumed run's saved ``config.yaml`` may only name classes of sdn3d, the training packages,
Lightning and torch (:data:`RESUME_TARGET_PREFIXES`): it is a file, and instantiating it runs what it names.
"""

from __future__ import annotations

import json
import logging
import os
import re
import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import lightning as L
import torch
from hydra.utils import instantiate
from omegaconf import DictConfig, OmegaConf

from lightning_modules._base import NonFiniteLossError
from lightning_modules.checkpointing import AtomicCheckpointIO, NonFiniteCheckpointError, remove_stale_temp_files
from sdn3d.errors import UserInputError
from sdn3d.io import write_json_atomic, write_text_atomic

__all__ = ["RESUME_TARGET_PREFIXES", "RunFailedError", "TrainingError", "check_resume_targets",
           "check_summary_file", "check_writable", "error_file", "error_sentence", "resolve_config",
           "resolve_resume", "run_training"]

log = logging.getLogger(__name__)

SAVED_CONFIG = "config.yaml"


class TrainingError(UserInputError, RuntimeError):
    """A run could not start or stopped for a reason the user can act on (message says which)."""


class RunFailedError(TrainingError):
    """A run started and ended with status ``failed`` (e.g. a non-finite loss); its summary says why.
    ``sdn3d-train`` prints it in one line and exits 1."""


#: The ``_target_`` prefixes a resumed run's saved config may name (and they must be classes). More can be
#: trusted from the command line only: ``resume_allow_targets=[helpers.]``.
RESUME_TARGET_PREFIXES = ("sdn3d.", "lightning_modules.", "datamodules.", "lightning.", "torch.")


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
_FAULT_LINKS = (("model", "nonfinite", "fault.nonfinite"),
                ("model", "max_skipped_batches", "fault.max_skipped_batches"),
                ("datamodule", "corrupt_sample", "fault.corrupt_sample"),
                ("datamodule", "max_skipped_fraction", "fault.max_skipped_fraction"))


def _targets(node: Any, key: str = "") -> Iterator[tuple[str, Any]]:
    """``(dotted key, value)`` of every ``_target_`` in a plain (unresolved) config tree."""
    if isinstance(node, Mapping):
        for name, value in node.items():
            if name == "_target_":
                yield key or "<root>", value
            else:
                yield from _targets(value, f"{key}.{name}" if key else str(name))
    elif isinstance(node, (list, tuple)):
        for i, value in enumerate(node):
            yield from _targets(value, f"{key}[{i}]")


def check_resume_targets(cfg: DictConfig, source: Path, extra: Sequence[str] = ()) -> None:
    """Refuse a saved config naming a ``_target_`` outside :data:`RESUME_TARGET_PREFIXES` (plus ``extra``), or
    one that is not a class, before anything is imported from it or instantiated.

    Raises:
        TrainingError: naming ``source``, the key and the target.
    """
    from hydra.utils import get_class

    allowed = tuple(RESUME_TARGET_PREFIXES) + tuple(str(e) for e in extra or ())
    tree = OmegaConf.to_container(cfg, resolve=False)
    for key, target in _targets(tree):
        if not isinstance(target, str) or not target.startswith(allowed):
            raise TrainingError(
                f"{source}: {key}._target_ = {target!r} is not allowed in a resumed run's config: it may only name "
                f"classes under {', '.join(allowed)}; remove that entry (or, if you trust it, pass "
                "resume_allow_targets=[<prefix>] on the command line)")
        try:
            get_class(target)
        except Exception as exc:  # noqa: BLE001 - any failure to find a class is the config's fault
            raise TrainingError(f"{source}: {key}._target_ = {target!r} is not a class that can be imported "
                                f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})") from None


def resolve_resume(cfg: DictConfig, overrides: list[str] | None = None) -> DictConfig:
    """``resume=<run dir>``: the run's saved config, its ``last.ckpt``, plus dotted CLI overrides.

    Group choices (``branch=...``) can not change on resume; dotted overrides such as
    ``trainer.max_epochs=30`` apply (e.g. to train a finished run longer). The saved config may only name
    trusted classes (:func:`check_resume_targets`; ``cfg.resume_allow_targets``, from the command line, adds
    prefixes).
    """
    run = Path(str(cfg.resume)).expanduser()
    saved = run / SAVED_CONFIG
    if not saved.is_file():
        raise TrainingError(f"resume={str(run)!r}: no {SAVED_CONFIG} there; is it an sdn3d-train run directory?")
    ckpt = run / "checkpoints" / "last.ckpt"
    if not ckpt.is_file():
        raise TrainingError(f"resume={str(run)!r}: no checkpoints/last.ckpt to resume from")
    base = OmegaConf.load(saved)
    if not isinstance(base, DictConfig):
        raise TrainingError(f"{saved}: not a config (a mapping of settings)")
    extra = cfg.get("resume_allow_targets") or ()
    check_resume_targets(base, saved, [extra] if isinstance(extra, str) else list(extra))
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


def check_summary_file(path: Path) -> None:
    """Fail early, with the path, when ``summary_file`` can not be appended to (the line is written last)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
        os.close(fd)
    except OSError as exc:
        raise TrainingError(f"summary_file {str(path)!r} is not writable: {exc.strerror or exc}") from exc


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
    """The run directory and ``summary_file``, checked writable, cleared of temp files a killed write left; a new
    run saves its resolved config there (``config.yaml``)."""
    run_dir = Path(str(cfg.run_dir))
    check_writable(run_dir)
    if cfg.get("summary_file"):
        check_summary_file(Path(str(cfg.summary_file)))
    if _rank_zero():  # a killed checkpoint or summary write left a temp file: this run is the only writer
        remove_stale_temp_files(run_dir / "checkpoints")
        remove_stale_temp_files(run_dir, (".json", ".yaml"))
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
    """How :func:`fit_and_test` went: ``status`` ok | failed (``error`` says why, ``error_file`` names the file
    at fault when known), the metrics, the best checkpoint, when fitting started (``time.perf_counter``), and
    which weights the test figures come from (``tested``: see :func:`fit_and_test`)."""

    status: str
    error: str | None
    metrics: dict[str, float]
    best: str | None
    started: float
    error_file: str | None = None
    tested: str | None = None


def fit_and_test(cfg: DictConfig, run: RunObjects) -> FitResult:
    """Fit (from ``ckpt_path`` if set), then test the best checkpoint (``test_after_fit``).

    The best checkpoint is the one the branch's ``monitor`` picks on the *validation* part (the split rules
    carve it from the training frames; :mod:`sdn3d.data.splits`): ``tested`` is ``'best'`` then, ``'final'``
    when no checkpoint was selected (the weights at the end of fitting), None when nothing was tested.

    A non-finite loss under ``fault.nonfinite=stop`` (or too many under ``skip``), or weights that became
    non-finite (no checkpoint is written then), end the fit with status ``failed``, not an exception.
    """
    trainer, model, datamodule = run.trainer, run.model, run.datamodule
    ckpt_path = cfg.get("ckpt_path")
    if ckpt_path and not Path(str(ckpt_path)).is_file():
        raise TrainingError(f"ckpt_path={str(ckpt_path)!r} does not exist")
    started = time.perf_counter()
    status, error, where = "ok", None, None
    try:
        trainer.fit(model, datamodule=datamodule, ckpt_path=str(ckpt_path) if ckpt_path else None)
    except (NonFiniteLossError, NonFiniteCheckpointError) as exc:
        status, error, where = "failed", error_sentence(exc), error_file(exc)
    fit_metrics = _scalars(trainer.callback_metrics)
    test_metrics: dict[str, float] = {}
    checkpoint = trainer.checkpoint_callback
    best = getattr(checkpoint, "best_model_path", "") or None
    tested = None
    if status == "ok" and cfg.get("test_after_fit") and not trainer.fast_dev_run and not trainer.interrupted:
        results = trainer.test(model, datamodule=datamodule, ckpt_path=best if best else None)
        test_metrics = _scalars(results[0]) if results else {}
        tested = "best" if best else "final"
    if status == "ok":  # TensorBoard's HPARAMS tab: the run's config next to its final metrics
        for logger in run.loggers:
            if type(logger).__name__ == "TensorBoardLogger":
                logger.log_hyperparams(run.params, metrics={**fit_metrics, **test_metrics} or {"status_ok": 1.0})
    return FitResult(status, error, {**fit_metrics, **test_metrics}, best, started, where, tested)


def _experiment_choice() -> str | None:
    """The ``experiment=`` of this Hydra run; None without one, or outside Hydra's main (a composed config)."""
    from hydra.core.hydra_config import HydraConfig

    if not HydraConfig.initialized():
        return None
    choice = HydraConfig.get().runtime.choices.get("experiment")
    return str(choice) if choice else None


def _rank_zero(run: RunObjects | None = None) -> bool:
    """Whether this process writes the run's files: the trainer's global rank 0, or (before there is a trainer)
    not a DDP child process."""
    if run is not None:
        return bool(run.trainer.is_global_zero)
    return all(int(os.environ.get(name, "0") or 0) == 0 for name in ("RANK", "LOCAL_RANK", "NODE_RANK"))


# A file named in a message: an absolute path with a suffix (e.g. in a loader worker's re-raised traceback).
_PATH_IN_TEXT = re.compile(r"(?<![\w.])/[^\s:'\"(),;]+\.[A-Za-z0-9]{1,8}\b")


def error_file(exc: BaseException) -> str | None:
    """The file at fault in ``exc`` or its causes (a ``path`` / ``filename`` attribute, else the first absolute
    path in its :func:`error_sentence`); None when none is named."""
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        seen.add(id(current))
        for attribute in ("path", "filename"):
            value = getattr(current, attribute, None)
            if value:
                return os.fspath(value)
        current = current.__cause__ or current.__context__
    match = _PATH_IN_TEXT.search(error_sentence(exc))  # a worker's traceback names source files: not those
    return match.group(0) if match else None


def error_sentence(exc: BaseException) -> str:
    """``exc`` in one line: a user's mistake as its message says it, anything else with its type in front.

    A loader worker's error arrives as "Caught X in DataLoader worker process N. Original Traceback ...": its
    last line (the original error) is the sentence.
    """
    text = str(exc).strip()
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    if lines and lines[0].startswith("Caught ") and "Original Traceback" in text:
        return lines[-1]
    first = lines[0] if lines else ""
    if isinstance(exc, UserInputError):
        return first or type(exc).__name__
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__


def write_summary(cfg: DictConfig, run_dir: Path, run: RunObjects | None, result: FitResult,
                  overrides: list[str] | None = None) -> dict[str, Any]:
    """The run's summary: ``<run dir>/summary.json`` and one line of ``summary_file`` (global rank 0).

    ``run`` is None when the run failed before its objects were built. ``skipped_batches`` counts batches the
    non-finite policy dropped; ``skipped_samples`` / ``skipped_fraction`` / ``skipped_files`` what the
    corrupt-sample policy left out (:meth:`datamodules._base.BranchDataModule.skip_summary`).
    """
    trainer = run.trainer if run is not None else None
    last = run_dir / "checkpoints" / "last.ckpt"
    skipped = {"skipped_samples": 0, "skipped_fraction": 0.0, "skipped_files": []}
    if run is not None and hasattr(run.datamodule, "skip_summary"):
        skipped.update(run.datamodule.skip_summary())
    branch = cfg.get("branch_name")
    summary = {
        "branch": str(branch) if branch is not None else None,
        "ablation": str(cfg.ablation.name) if branch == "geometric" and cfg.get("ablation") else None,
        "experiment": _experiment_choice(),
        "run_dir": str(run_dir.resolve()),
        "best_ckpt": str(Path(result.best).resolve()) if result.best else None,
        "last_ckpt": str(last.resolve()) if last.is_file() else None,
        "metrics": result.metrics,
        # Which weights the test/ metrics come from: 'best' = best_ckpt, selected by `selected_by` on the
        # validation part (never on test); 'final' = the weights at the end of fitting; None = not tested.
        "tested_checkpoint": result.tested,
        "selected_by": (f"{cfg.monitor} ({cfg.get('monitor_mode', 'min')}) on the validation part"
                        if cfg.get("monitor") else None),
        "global_step": int(trainer.global_step) if trainer is not None else 0,
        "epoch": int(trainer.current_epoch) if trainer is not None else 0,
        "skipped_batches": int(getattr(run.model, "skipped_batches", 0)) if run is not None else 0,
        **skipped,
        "overrides": list(overrides or []),
        "seed": int(cfg.seed),
        "wall_s": round(time.perf_counter() - result.started, 3),
        "finished": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "status": result.status,
        "error": result.error,
        "error_file": result.error_file,
    }
    if _rank_zero(run):
        write_json_atomic(run_dir / "summary.json", summary)
        if cfg.get("summary_file"):
            _append_summary(Path(str(cfg.summary_file)), summary)
    return summary


def _record_failure(cfg: DictConfig, run_dir: Path, run: RunObjects | None, exc: BaseException, started: float,
                    overrides: list[str] | None) -> None:
    """Write the summary of a run stopped by ``exc`` (best effort: a full disk may refuse it too)."""
    metrics = _scalars(run.trainer.callback_metrics) if run is not None else {}
    best = getattr(run.trainer.checkpoint_callback, "best_model_path", "") or None if run is not None else None
    result = FitResult("failed", error_sentence(exc), metrics, best, started, error_file(exc))
    try:
        write_summary(cfg, run_dir, run, result, overrides)
    except Exception as write_error:  # noqa: BLE001 - the run's own error is the one to raise
        log.error("could not record the failed run's summary in %s: %s", run_dir, write_error)


def run_training(cfg: DictConfig, overrides: list[str] | None = None) -> dict[str, Any]:
    """Train (and test) one branch as configured; returns the run summary (also written to disk).

    ``overrides`` are the command line's (Hydra's task overrides): recorded in the summary, and applied to a
    resumed run's saved config. Once the run directory and ``summary_file`` are found writable, whatever
    stops the run is recorded in its summary (status ``failed``, ``error``, ``error_file``) and then raised.

    Raises:
        TrainingError: bad resume target / checkpoint / unwritable output (before the run starts).
        RunFailedError: the run ended with status ``failed``: a non-finite loss under ``fault.nonfinite=stop``
            or too many under ``skip``, or non-finite weights (the last good checkpoint stays in
            ``<run>/checkpoints``).
        Any other error of the run (a corrupt sample, a full disk, a bug), after recording it.
    """
    cfg = resolve_config(cfg, overrides)
    run_dir = Path(str(cfg.run_dir))
    check_writable(run_dir)
    with _run_lock(run_dir):
        return _run_locked(cfg, overrides)


#: The lock file of a run directory while ``sdn3d-train`` writes it (:func:`sdn3d.io.writer_lock`).
RUN_LOCK = ".sdn3d-run.lock"


def _run_lock(run_dir: Path) -> Any:
    """One writer per run directory: the lock of :data:`RUN_LOCK`, taken by the launching process only (the
    processes a multi-device strategy starts for ranks > 0 run inside the launcher's lock)."""
    from contextlib import nullcontext

    from sdn3d.io import writer_lock

    if any(os.environ.get(name, "0") != "0" for name in ("LOCAL_RANK", "NODE_RANK", "RANK")):
        return nullcontext()
    return writer_lock(run_dir / RUN_LOCK, f"run directory {str(run_dir)!r}")


def _run_locked(cfg: DictConfig, overrides: list[str] | None) -> dict[str, Any]:
    """:func:`run_training` once the run directory's lock is held."""
    run_dir = prepare_run_dir(cfg)
    started = time.perf_counter()
    run: RunObjects | None = None
    try:
        configure_process(cfg)
        run = build_objects(cfg)
        result = fit_and_test(cfg, run)
    except Exception as exc:
        _record_failure(cfg, run_dir, run, exc, started, overrides)
        raise
    summary = write_summary(cfg, run_dir, run, result, overrides)
    if result.status != "ok":
        raise RunFailedError(f"{result.error} (run directory: {run_dir})")
    if _rank_zero(run):  # checkpoints/inference.pt: what sdn3d-edit run= loads instead (sdn3d.inference_export)
        from sdn3d.runs import export_run_checkpoint

        try:
            log.info("inference export: %s", export_run_checkpoint(run_dir / "summary.json"))
        except (UserInputError, OSError) as exc:
            log.warning("no inference export written (%s); run= loads the checkpoint", exc)
    return summary
