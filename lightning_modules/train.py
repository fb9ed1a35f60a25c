"""The training run behind ``sdn3d-train``: config -> datamodule, module, trainer -> fit, test, summary.

Kept apart from the Hydra entry point (:mod:`sdn3d.cli.train`) so tests and notebooks can call
:func:`run_training` with a composed config. Hydra composes everything (branch, experiment, its recipe,
command-line overrides); :func:`run_training` runs the stages :func:`resolve_config`, :func:`check_start`,
:func:`prepare_run_dir`, :func:`configure_process`, :func:`build_objects`, :func:`fit_and_test` and
:func:`write_summary`.

Every attempt that starts (once its run directory and ``summary_file`` are found writable) records its summary
whatever stops it: ``status`` ok / failed, ``error`` (one sentence), ``error_file`` (the file at fault, when known)
and what the fault policies skipped, as one line of ``<run dir>/summary_log.jsonl`` and of ``summary_file``, and as
``<run dir>/summary.json`` unless it is a resume that failed before writing a checkpoint (the run's figures stay
those of the attempt that made its checkpoints). Mistakes found before the start (:func:`resolve_resume`,
:func:`check_start`) write nothing.

Runs are relocatable: the saved ``config.yaml`` refers to ``${run_dir}`` (:func:`saved_config_text`), and a
resume takes the run directory from where it is now (:func:`resolve_resume`). A resumed run's saved
``config.yaml`` may only name classes of sdn3d, the training packages, Lightning and torch
(:data:`RESUME_TARGET_PREFIXES`): it is a file, and instantiating it runs what it names.
"""

from __future__ import annotations

import json
import logging
import os
import re
import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

import lightning as L
import torch
from hydra.utils import instantiate
from omegaconf import DictConfig, ListConfig, OmegaConf
from omegaconf.errors import OmegaConfBaseException

from lightning_modules._base import NonFiniteLossError
from lightning_modules.checkpointing import AtomicCheckpointIO, NonFiniteCheckpointError, remove_stale_temp_files
from sdn3d.errors import UserInputError
from sdn3d.io import write_json_atomic, write_text_atomic

__all__ = ["RESUME_TARGET_PREFIXES", "SUMMARY_LOG", "RunFailedError", "StartPoint", "TrainingError",
           "check_resume_targets", "check_start", "check_summary_file", "check_threads", "check_writable", "error_file",
           "error_sentence", "resolve_config", "resolve_resume", "run_training", "saved_config_text"]

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


class _Absent:
    """The value :func:`_select` gives for a key a config does not have."""


_ABSENT = _Absent()


def _select(cfg: DictConfig, key: str) -> Any:
    """The node at dotted ``key`` of ``cfg`` (unresolved), or :data:`_ABSENT` when there is none."""
    node: Any = cfg
    for part in key.split("."):
        if isinstance(node, DictConfig) and part in node:
            node = node._get_node(part)
        elif isinstance(node, ListConfig) and part.lstrip("-").isdigit() and -len(node) <= int(part) < len(node):
            node = node._get_node(int(part))
        else:
            return _ABSENT
    return node


#: Command-line keys ``resume=`` consumes itself (the rest of the command line is applied to the saved config).
_RESUME_OWN_KEYS = ("resume",)
#: Keys that cannot change on resume: a resumed run writes into its own directory and continues from its last.ckpt.
_RESUME_FIXED_KEYS = ("run_dir", "ckpt_path")


def _apply_command_line(target: DictConfig, overrides: list[str] | None, source: Path) -> list[str]:
    """Apply the command line ``overrides`` of ``resume=`` to ``target``, the run's saved config (``source``), in
    place; returns the overrides applied. Every override is applied or refused, none is dropped.

    A resumed run's config is its saved, resolved ``config.yaml``, which Hydra does not compose, so Hydra can not
    apply the command line to it. The values are read with Hydra's own override grammar, as Hydra reads them
    everywhere else: a multirun hands them over escaped (``trainer.max_time=00\\:01\\:00\\:00``), and plain YAML
    reads some strings differently (``1:30`` is a number to YAML 1.1). As in Hydra, ``key=value`` changes a setting
    the config has, ``+key=value`` adds one it lacks, ``++key=value`` sets either way, ``~key`` deletes one.
    ``hydra.*`` overrides are Hydra's own (it applies them).

    Raises:
        TrainingError: naming the override: a config group choice (``branch=``, ``experiment=``, ``data=``, ...:
            the saved config is already composed), ``run_dir=`` or ``ckpt_path=``, a setting the saved config does
            not have (or, with ``+``, already has).
    """
    from hydra.core.override_parser.overrides_parser import OverridesParser
    from hydra.errors import HydraException

    texts = [str(o) for o in overrides or []]
    try:
        parsed = OverridesParser.create().parse_overrides(texts)
    except HydraException as exc:
        raise TrainingError(f"resume: bad command line override: {' '.join(str(exc).split())}") from exc
    groups = _group_names()
    applied = []
    for text, override in zip(texts, parsed, strict=True):
        key = override.key_or_group
        if key in _RESUME_OWN_KEYS or key == "hydra" or key.startswith(("hydra.", "hydra/")):
            continue
        where = f"{text!r} with resume= (the run's config is its saved {source})"
        if key in _RESUME_FIXED_KEYS:
            raise TrainingError(f"{where}: {key} can not be given: a resumed run writes into its own directory and "
                                "continues from its checkpoints/last.ckpt; to train from another checkpoint into a new "
                                f"run directory, start a new run with ckpt_path=<checkpoint> instead of resume=")
        node = _select(target, key)
        if override.package is not None or "/" in key or key in groups or isinstance(node, DictConfig) and not (
                override.is_delete() or override.is_force_add()):
            raise TrainingError(f"{where}: {key!r} is a config group (or a section of settings): its choice can not "
                                "change on resume; set single values instead (e.g. trainer.max_epochs=30), or start a "
                                "new run")
        if override.is_sweep_override():
            raise TrainingError(f"{where}: a sweep can not be applied to one resumed run")
        if override.is_delete():
            if node is _ABSENT:
                raise TrainingError(f"{where}: the run's config has no {key!r} to delete")
            parent, _, leaf = key.rpartition(".")
            container = _select(target, parent) if parent else target
            del container[int(leaf) if isinstance(container, ListConfig) else leaf]
        elif override.is_add() and node is not _ABSENT:
            raise TrainingError(f"{where}: the run's config already has {key!r}: drop the '+' to change it")
        elif not (override.is_add() or override.is_force_add()) and node is _ABSENT:
            group = "" if "." in key else (" (a config group's choice, such as branch= or experiment=, can not "
                                           "change on resume)")
            raise TrainingError(f"{where}: the run's config has no setting {key!r}{group}; a typo? To add a setting, "
                                f"write +{text}")
        else:
            OmegaConf.update(target, key, override.value(), merge=False, force_add=True)
        applied.append(text)
    return applied


def _group_names() -> set[str]:
    """The config groups of this Hydra run (``branch``, ``data``, ``experiment``, ...), empty outside Hydra's main."""
    from hydra.core.hydra_config import HydraConfig

    if not HydraConfig.initialized():
        return set()
    return {str(k) for k in HydraConfig.get().runtime.choices}


def _rebase(node: Any, old: str, new: str) -> Any:
    """``node`` (a plain config tree) with every string that is the directory ``old`` or a path under it moved to the
    same place under ``new``."""
    if isinstance(node, Mapping):
        return {k: _rebase(v, old, new) for k, v in node.items()}
    if isinstance(node, list):
        return [_rebase(v, old, new) for v in node]
    if isinstance(node, str) and (node == old or node.startswith(old + "/")):
        return new + node[len(old):]
    return node


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
    try:  # a target may be a reference (model._target_: ${ablation.module}): check what it names
        tree = OmegaConf.to_container(cfg, resolve=True)
    except OmegaConfBaseException as exc:
        raise TrainingError(f"{source}: not a config that can be read ({' '.join(str(exc).split())[:200]})") from None
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
    """``resume=<run dir>``: the run's saved config, its ``last.ckpt``, plus the command line ``overrides``.

    The run is where ``resume=`` says it is: every path of its saved config that lay in the directory it was trained
    in (``run_dir`` as saved: checkpoints, TensorBoard, ``trainer.default_root_dir``) is taken from the same place in
    this directory, so a copied or moved run resumes into itself. ``summary_file`` (the shared one-line-per-run log)
    is this command's, as for a new run. The command line is applied to the saved config or refused
    (:func:`_apply_command_line`: ``trainer.max_epochs=30``, ``threads=1``, ``summary_file=...`` apply; group
    choices such as ``branch=`` can not change). The saved config may only name trusted classes
    (:func:`check_resume_targets`; ``cfg.resume_allow_targets``, from the command line, adds prefixes).
    """
    run = Path(os.path.abspath(Path(str(cfg.resume)).expanduser()))
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
    trained_in = base.get("run_dir")
    if isinstance(trained_in, str) and trained_in.rstrip("/") and trained_in.rstrip("/") != str(run):
        base = OmegaConf.create(_rebase(OmegaConf.to_container(base, resolve=False), trained_in.rstrip("/"),
                                        str(run)))
    # The saved config is resolved: link the fault policies to fault.* again, so that `fault.nonfinite=skip`
    # on resume reaches the module and datamodule (as conf/train.yaml does for a new run).
    for node, key, source in _FAULT_LINKS:
        if isinstance(base.get(node), DictConfig) and OmegaConf.select(base, source) is not None:
            base[node][key] = "${" + source + "}"
    base.summary_file = cfg.get("summary_file")
    _apply_command_line(base, overrides, saved)
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


@dataclass
class StartPoint:
    """Where fitting starts: the training checkpoint ``ckpt_path`` names (None: from scratch), how far it had got
    (``epochs`` whose training finished, optimiser ``steps``), and whether that already reaches the config's budget
    (``finished``: fitting has nothing left to do; ``budget`` says which limit and ``larger`` a larger one, for
    messages); ``checkpoint_dirs``: where its checkpoint callbacks wrote (``{callback state key: dirpath}``)."""

    checkpoint: Path | None = None
    epochs: int = 0
    steps: int = 0
    finished: bool = False
    budget: str = ""
    larger: str = ""
    checkpoint_dirs: dict[str, str] = field(default_factory=dict)


def _budget(cfg: DictConfig) -> tuple[int | None, int | None]:
    """``(max_epochs, max_steps)`` of the trainer config, None for no limit (Lightning's rules: both unset is 1000
    epochs; -1 is none)."""
    trainer = cfg.get("trainer") or {}
    epochs, steps = trainer.get("max_epochs"), trainer.get("max_steps", -1)
    steps = None if steps in (None, -1) else int(steps)
    if epochs is None:
        return (1000 if steps is None else None), steps
    return (None if int(epochs) == -1 else int(epochs)), steps


def check_start(cfg: DictConfig) -> StartPoint:
    """Check the checkpoint training continues from (``ckpt_path``; ``resume=`` sets it to the run's ``last.ckpt``)
    before anything is written: it must be a Lightning *training* checkpoint of this branch, and the config's budget
    (``trainer.max_epochs`` / ``max_steps``) may not be smaller than what it has trained. Its tensors are mapped, not
    read.

    Raises:
        TrainingError: naming the file: missing or unreadable, an inference export or other weights-only file (no
            optimiser or loop state to continue), another branch's checkpoint, or a budget below its progress.
    """
    from sdn3d.inference_export import is_inference_export
    from sdn3d.io import checkpoint_branch, load_torch_file

    if not cfg.get("ckpt_path"):
        return StartPoint()
    path = Path(str(cfg.ckpt_path)).expanduser()
    what = f"resume={str(cfg.resume)!r}: its checkpoint" if cfg.get("resume") else "ckpt_path"
    if not path.is_file():
        raise TrainingError(f"{what} {str(path)!r} does not exist")
    try:
        content = load_torch_file(path, "checkpoint", mmap=True)
    except UserInputError:  # mmap needs torch's zip format: an old-format file is read whole (or refused)
        try:
            content = load_torch_file(path, "checkpoint")
        except UserInputError as exc:
            raise TrainingError(f"{what}: {exc}") from exc
    if is_inference_export(content):
        raise TrainingError(
            f"{what} {str(path)!r} is an sdn3d inference export (weights only, as sdn3d-export-weights and "
            "checkpoints/inference.pt hold them): training can only continue from a Lightning training checkpoint, "
            "which also holds the optimiser and loop state (a run's checkpoints/last.ckpt or best-*.ckpt)")
    needed = ("state_dict", "pytorch-lightning_version", "optimizer_states", "loops")
    lacking = [k for k in needed if not isinstance(content, Mapping) or k not in content]
    if lacking:
        raise TrainingError(f"{what} {str(path)!r} is not a Lightning training checkpoint (it lacks "
                            f"{', '.join(map(repr, lacking))}): training can only continue from one (a run's "
                            "checkpoints/last.ckpt or best-*.ckpt)")
    branch, held = cfg.get("branch_name"), checkpoint_branch(content)
    if branch and held and held != str(branch):
        raise TrainingError(f"{what} {str(path)!r} holds the {held} branch's weights, not the {branch} branch's")
    try:
        epochs = int(content["loops"]["fit_loop"]["epoch_progress"]["current"]["processed"])
    except (KeyError, TypeError, ValueError):
        epochs = int(content.get("epoch") or 0)
    steps = int(content.get("global_step") or 0)
    max_epochs, max_steps = _budget(cfg)
    done = f"{epochs} epoch(s), {steps} optimiser step(s)"
    if max_epochs is not None and max_epochs < epochs or max_steps is not None and max_steps < steps:
        limit = (f"trainer.max_epochs={max_epochs}" if max_epochs is not None and max_epochs < epochs
                 else f"trainer.max_steps={max_steps}")
        raise TrainingError(f"{what} {str(path)!r} has trained {done}: {limit} is less than that; give a budget of "
                            "at least what it has trained (more to train it longer)")
    reached = []
    if max_epochs is not None and epochs >= max_epochs:
        reached.append(f"trainer.max_epochs={max_epochs}")
    if max_steps is not None and steps >= max_steps:
        reached.append(f"trainer.max_steps={max_steps}")
    states = content.get("callbacks")
    dirs = {str(k): v["dirpath"] for k, v in states.items() if isinstance(v, Mapping) and isinstance(
        v.get("dirpath"), str)} if isinstance(states, Mapping) else {}
    if not reached:
        return StartPoint(path, epochs, steps, checkpoint_dirs=dirs)
    more = (f"trainer.max_epochs={epochs + 10}" if max_epochs is not None and epochs >= max_epochs
            else f"trainer.max_steps={steps + 1000}")
    return StartPoint(path, epochs, steps, True, f"{done}, all of its budget ({' and '.join(reached)})", more, dirs)


# A value that only refers to other settings: ${run_dir}/checkpoints, ${data}, ${fault.nonfinite} (no resolver).
_REFERENCE = re.compile(r"\$\{[A-Za-z_][\w.]*\}")


def _keep_references(raw: Any, resolved: Any) -> Any:
    """``resolved`` (a plain config tree), except where ``raw`` (the same tree unresolved) holds a string made of
    references to other settings only: that string is kept as it is."""
    if isinstance(raw, Mapping) and isinstance(resolved, Mapping):
        return {k: _keep_references(raw.get(k), v) for k, v in resolved.items()}
    if isinstance(raw, list) and isinstance(resolved, list) and len(raw) == len(resolved):
        return [_keep_references(r, v) for r, v in zip(raw, resolved, strict=True)]
    if isinstance(raw, str) and "${" in raw and "${" not in _REFERENCE.sub("", raw) and "\\${" not in raw:
        return raw
    return resolved


def saved_config_text(cfg: DictConfig) -> str:
    """A new run's ``config.yaml``: its config resolved, except that a setting which refers to others keeps the
    reference (``callbacks.model_checkpoint.dirpath: ${run_dir}/checkpoints``, ``datamodule.data: ${data}``). So a
    resume (:func:`resolve_resume`) that sets ``run_dir`` to where the run is now, or overrides ``data.root`` or
    ``seed``, changes every setting that follows from it, as it would in a new run. Resolvers (``${hydra:...}``,
    ``${oc.env:...}``) are resolved: the file does not depend on the environment it was written in."""
    raw = OmegaConf.to_container(cfg, resolve=False)
    resolved = OmegaConf.to_container(cfg, resolve=True)
    return OmegaConf.to_yaml(OmegaConf.create(_keep_references(raw, resolved)))


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
        write_text_atomic(run_dir / SAVED_CONFIG, saved_config_text(cfg))
    return run_dir


def check_threads(cfg: DictConfig) -> None:
    """Refuse ``threads`` unless it is null (PyTorch's default) or a positive integer, as ``sdn3d-edit`` does.

    Raises:
        TrainingError: naming the setting and the value given.
    """
    threads = cfg.get("threads")
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int) or threads < 1):
        raise TrainingError(f"threads must be a positive integer (torch CPU threads) or null for PyTorch's default, "
                            f"got {threads!r}")


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
    ckpt_path = cfg.get("ckpt_path")  # checked by check_start before the run started
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


#: Every attempt on a run directory (a new run, each resume), ok or failed, appends its summary here.
SUMMARY_LOG = "summary_log.jsonl"


@dataclass
class _Before:
    """What a run directory held when an attempt started: its summary (a resume's earlier one; None: none or
    unreadable) and its checkpoints (name -> size and modification time)."""

    summary: dict[str, Any] | None
    checkpoints: dict[str, tuple[int, int]]

    @classmethod
    def of(cls, cfg: DictConfig, run_dir: Path) -> _Before:
        summary = None
        if cfg.get("resume"):
            try:
                loaded = json.loads((run_dir / "summary.json").read_text(encoding="utf-8"))
                summary = loaded if isinstance(loaded, dict) else None
            except (OSError, UnicodeDecodeError, ValueError):
                summary = None
        return cls(summary, _checkpoint_files(run_dir))


def _checkpoint_files(run_dir: Path) -> dict[str, tuple[int, int]]:
    folder = run_dir / "checkpoints"
    if not folder.is_dir():
        return {}
    return {p.name: (p.stat().st_size, p.stat().st_mtime_ns) for p in folder.iterdir() if p.suffix == ".ckpt"}


def write_summary(cfg: DictConfig, run_dir: Path, run: RunObjects | None, result: FitResult,
                  overrides: list[str] | None = None, before: _Before | None = None) -> dict[str, Any]:
    """The attempt's summary: ``<run dir>/summary.json``, one line of ``<run dir>/summary_log.jsonl`` and one of
    ``summary_file`` (global rank 0).

    A resume (``before`` holds the run's earlier summary) that failed without writing a checkpoint leaves
    ``summary.json`` as it was: its failure goes to the two logs only, and the run's figures stay those of the
    attempt that made its checkpoints. A resumed run's summary keeps the ``experiment`` and ``overrides`` the run
    was started with; ``resume_overrides`` is the command line of the resume (None: never resumed).

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
    earlier = before.summary if before is not None and before.summary is not None else None
    resumed = bool(cfg.get("resume"))
    started_with = earlier.get("overrides") if earlier is not None else None
    summary = {
        "branch": str(branch) if branch is not None else None,
        "ablation": str(cfg.ablation.name) if branch == "geometric" and cfg.get("ablation") else None,
        "experiment": earlier.get("experiment") if earlier is not None else _experiment_choice(),
        "variant": str(cfg.variant) if cfg.get("variant") is not None else None,
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
    if _rank_zero(run):
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


def _record_failure(cfg: DictConfig, run_dir: Path, run: RunObjects | None, exc: BaseException, started: float,
                    overrides: list[str] | None, before: _Before | None = None) -> None:
    """Write the summary of a run stopped by ``exc`` (best effort: a full disk may refuse it too)."""
    metrics = _scalars(run.trainer.callback_metrics) if run is not None else {}
    best = getattr(run.trainer.checkpoint_callback, "best_model_path", "") or None if run is not None else None
    result = FitResult("failed", error_sentence(exc), metrics, best, started, error_file(exc))
    try:
        write_summary(cfg, run_dir, run, result, overrides, before)
    except Exception as write_error:  # noqa: BLE001 - the run's own error is the one to raise
        log.error("could not record the failed run's summary in %s: %s", run_dir, write_error)


def run_training(cfg: DictConfig, overrides: list[str] | None = None) -> dict[str, Any]:
    """Train (and test) one branch as configured; returns the run summary (also written to disk).

    ``overrides`` are the command line's (Hydra's task overrides): recorded in the summary, and applied to a
    resumed run's saved config (:func:`resolve_resume`). Before anything is written, the checkpoint training
    continues from is checked (:func:`check_start`). Once the run directory and ``summary_file`` are found
    writable, whatever stops the run is recorded (status ``failed``, ``error``, ``error_file``; a resume that
    failed before writing a checkpoint leaves ``summary.json`` as it was: :func:`write_summary`) and then raised.

    A resume of a run that has trained its whole budget and whose summary says ok does nothing: it logs so and
    returns that summary, changing no file.

    Raises:
        TrainingError: bad resume target / override / checkpoint (an export, another branch's, a budget below what
            it trained) / ``threads`` not null or a positive integer / unwritable output (before the run starts).
        RunFailedError: the run ended with status ``failed``: a non-finite loss under ``fault.nonfinite=stop``
            or too many under ``skip``, or non-finite weights (the last good checkpoint stays in
            ``<run>/checkpoints``).
        Any other error of the run (a corrupt sample, a full disk, a bug), after recording it.
    """
    cfg = resolve_config(cfg, overrides)
    check_threads(cfg)
    start = check_start(cfg)
    run_dir = Path(str(cfg.run_dir))
    check_writable(run_dir)
    with _run_lock(run_dir):
        return _run_locked(cfg, overrides, start)


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


def _run_locked(cfg: DictConfig, overrides: list[str] | None, start: StartPoint) -> dict[str, Any]:
    """:func:`run_training` once the run directory's lock is held."""
    run_dir = Path(str(cfg.run_dir))
    before = _Before.of(cfg, run_dir)
    if cfg.get("resume") and start.finished and before.summary is not None and before.summary.get("status") == "ok":
        log.warning("resume=%s: nothing to do: the run has trained %s; its summary (status ok) and checkpoints are "
                    "left as they are. To train it longer, give a larger budget, e.g. %s", cfg.resume, start.budget,
                    start.larger)
        return before.summary
    run_dir = prepare_run_dir(cfg)
    started = time.perf_counter()
    run: RunObjects | None = None
    try:
        configure_process(cfg)
        run = build_objects(cfg, start)
        result = fit_and_test(cfg, run)
    except Exception as exc:
        _record_failure(cfg, run_dir, run, exc, started, overrides, before)
        raise
    summary = write_summary(cfg, run_dir, run, result, overrides, before)
    if result.status != "ok":
        raise RunFailedError(f"{result.error} (run directory: {run_dir})")
    if _rank_zero(run):  # checkpoints/inference.pt: what sdn3d-edit run= loads instead (sdn3d.inference_export)
        from sdn3d.runs import export_run_checkpoint

        try:
            log.info("inference export: %s", export_run_checkpoint(run_dir / "summary.json"))
        except (UserInputError, OSError) as exc:
            log.warning("no inference export written (%s); run= loads the checkpoint", exc)
    return summary
