"""A run directory: checked writable, cleared of the temp files a killed write left, and the run's saved config."""

from __future__ import annotations

import logging
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from omegaconf import DictConfig, OmegaConf

from sdn3d.io import write_text_atomic
from sdn3d.training.errors import TrainingError

__all__ = ["SAVED_CONFIG", "check_new_run_dir", "check_summary_file", "check_writable", "is_launcher",
           "prepare_run_dir", "remove_stale_temp_files", "save_hydra_record", "saved_config_text"]

log = logging.getLogger(__name__)

SAVED_CONFIG = "config.yaml"

# sdn3d.io.atomic_write's temp files: ".<name>.<random>.tmp" next to <name>.
_TEMP_NAME = re.compile(r"^\.(?P<name>.+)\.[A-Za-z0-9_]+\.tmp$")


def is_launcher() -> bool:
    """Whether this process is not a child a multi-device strategy started for a rank > 0 (before there is a
    trainer to ask)."""
    return all(int(os.environ.get(name, "0") or 0) == 0 for name in ("RANK", "LOCAL_RANK", "NODE_RANK"))


def remove_stale_temp_files(folder: Path, suffixes: tuple[str, ...] = (".ckpt",)) -> list[Path]:
    """Delete the temp files a killed atomic write left in ``folder`` (``.<name>.<random>.tmp`` whose
    ``<name>`` ends with one of ``suffixes``); returns them. Call it only where no write is under way."""
    removed = []
    if not folder.is_dir():
        return removed
    for path in sorted(folder.iterdir()):
        match = _TEMP_NAME.match(path.name)
        if match and match["name"].endswith(suffixes) and path.is_file():
            try:
                path.unlink()
            except FileNotFoundError:
                continue
            removed.append(path)
    if removed:
        log.info("removed %d stale temp file(s) of killed checkpoint writes in %s", len(removed), folder)
    return removed

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
    if is_launcher():  # a killed checkpoint or summary write left a temp file: this run is the only writer
        remove_stale_temp_files(run_dir / "checkpoints")
        remove_stale_temp_files(run_dir, (".json", ".yaml"))
    if not cfg.get("resume"):
        write_text_atomic(run_dir / SAVED_CONFIG, saved_config_text(cfg))
        save_hydra_record(cfg, run_dir)
    return run_dir



#: What marks a directory as holding a run (a new run would replace them).
_RUN_FILES = (SAVED_CONFIG, "summary.json", "summary_log.jsonl", "checkpoints")


def check_new_run_dir(cfg: DictConfig) -> None:
    """Refuse a new run (no ``resume=``) into a directory that holds a run: its checkpoints, ``inference.pt`` and
    ``summary.json`` would be replaced. ``overwrite=true`` allows it.

    Raises:
        TrainingError: naming the directory, what it holds and the three ways on.
    """
    if cfg.get("resume") or cfg.get("overwrite"):
        return
    run_dir = Path(str(cfg.run_dir))
    found = [name for name in _RUN_FILES if (run_dir / name).is_file() or (run_dir / name).is_dir() and any(
        (run_dir / name).iterdir())]
    if found:
        raise TrainingError(
            f"run directory {str(run_dir)!r} already holds a run ({', '.join(found)}): a new run would replace its "
            f"checkpoints, inference.pt and summary.json. Continue it with resume={run_dir}, train into a new "
            "directory (leave run_dir= and hydra.run.dir= unset for a new time-stamped one), or replace it with "
            "overwrite=true")


def save_hydra_record(cfg: DictConfig, run_dir: Path) -> None:
    """A new run's ``.hydra/`` (``config.yaml``, ``hydra.yaml``, ``overrides.yaml``), as Hydra itself writes them,
    once the run has started: Hydra would write them before the task runs, so a training refused before it starts
    (the run directory's lock, a run already there) replaced another run's record (``conf/train.yaml`` sets
    ``hydra.output_subdir`` to null). Nothing outside Hydra's main (a composed config)."""
    from hydra.core.hydra_config import HydraConfig

    if not HydraConfig.initialized():
        return
    hydra_cfg = HydraConfig.instance().cfg
    task = OmegaConf.create(OmegaConf.to_container(cfg, resolve=False))
    for name, node in (("config.yaml", task), ("hydra.yaml", hydra_cfg),
                       ("overrides.yaml", HydraConfig.get().overrides.task)):
        write_text_atomic(run_dir / ".hydra" / name, OmegaConf.to_yaml(node))
