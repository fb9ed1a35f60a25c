"""``resume=<run dir>``: a run's saved config, relocated to where the run is now, with the command line applied.

Runs are relocatable: the saved ``config.yaml`` refers to ``${run_dir}``
(:func:`sdn3d.training.rundir.saved_config_text`), and a resume takes the run directory from where it is now
(:func:`resolve_resume`). A resumed run's saved
``config.yaml`` may only name classes of sdn3d, the training packages, Lightning and torch
(:data:`RESUME_TARGET_PREFIXES`): it is a file, and instantiating it runs what it names.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from omegaconf import DictConfig, ListConfig, OmegaConf
from omegaconf.errors import OmegaConfBaseException

from sdn3d.training.errors import TrainingError
from sdn3d.training.rundir import SAVED_CONFIG
from sdn3d.training.start import StartPoint

__all__ = ["RESUME_TARGET_PREFIXES", "check_resume_targets", "finished_resume", "resolve_config", "resolve_resume"]

log = logging.getLogger(__name__)


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



def resolve_config(cfg: DictConfig, overrides: list[str] | None = None) -> DictConfig:
    """The run's config: ``cfg`` as Hydra composed it, or for ``resume=<run dir>`` that run's saved config
    with the dotted command-line ``overrides`` (:func:`resolve_resume`)."""
    return resolve_resume(cfg, overrides) if cfg.get("resume") else cfg



def finished_resume(cfg: DictConfig, start: StartPoint, earlier: Mapping[str, Any] | None) -> Mapping[str, Any] | None:
    """A resume of a run that has trained its whole budget (``start.finished``) and whose summary (``earlier``) says
    ok has nothing to do: that summary, after logging so (no file changes); None otherwise."""
    if cfg.get("resume") and start.finished and earlier is not None and earlier.get("status") == "ok":
        log.warning("resume=%s: nothing to do: the run has trained %s; its summary (status ok) and checkpoints are "
                    "left as they are. To train it longer, give a larger budget, e.g. %s", cfg.resume, start.budget,
                    start.larger)
        return earlier
    return None
