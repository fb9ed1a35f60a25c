"""One writer per run directory."""

from __future__ import annotations

import os
from contextlib import AbstractContextManager, nullcontext
from pathlib import Path
from typing import Any

from sdn3d.io import writer_lock

__all__ = ["RUN_LOCK", "run_lock"]

#: The lock file of a run directory while ``sdn3d-train`` writes it (:func:`sdn3d.io.writer_lock`).
RUN_LOCK = ".sdn3d-run.lock"


def run_lock(run_dir: Path) -> AbstractContextManager[Any]:
    """One writer per run directory: the lock of :data:`RUN_LOCK`, taken by the launching process only (the
    processes a multi-device strategy starts for ranks > 0 run inside the launcher's lock).

    Raises (on entering):
        sdn3d.io.BusyError: another live process holds the lock (the message names it and the lock file).
    """
    if any(os.environ.get(name, "0") != "0" for name in ("LOCAL_RANK", "NODE_RANK", "RANK")):
        return nullcontext()
    return writer_lock(run_dir / RUN_LOCK, f"run directory {str(run_dir)!r}")
