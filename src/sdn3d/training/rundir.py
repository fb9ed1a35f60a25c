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

__all__ = ["SAVED_CONFIG", "check_summary_file", "check_writable", "is_launcher", "prepare_run_dir",
           "remove_stale_temp_files", "saved_config_text"]

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
    return run_dir

