"""Fault injection for processes: kill a tool the hard way and look at what it leaves behind.

Typical use (Linux; the helpers read ``/proc``)::

    with process_group([sys.executable, "-m", "sdn3d.cli.synth", ...], log=tmp_path / "log") as proc:
        wait_for_files(tmp_path, ".data.partial-*/**/*.png", count=2, proc=proc)
        workers = group_members(proc.pid, exclude_leader=True)   # snapshot before the kill
        sigkill_leader(proc)                                      # SIGKILL the parent only
        assert wait_until_gone(workers, timeout=5) == []          # nothing it started survives

:func:`process_group` starts the command as the leader of a new session (its own process group), so
every process it forks stays findable by group id after the leader is gone (orphans are re-parented,
their parent id changes, their group id does not); on exit it SIGKILLs whatever of the group is left,
so a failing test never leaves busy processes behind. A process is identified by ``(pid, start
time)``, so a pid reused by an unrelated process is not mistaken for a survivor; zombies count as dead.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

__all__ = [
    "ProcInfo",
    "proc_info",
    "all_processes",
    "group_members",
    "descendants",
    "alive",
    "survivors",
    "wait_for",
    "wait_for_files",
    "start_in_new_group",
    "sigkill_leader",
    "kill_group",
    "wait_until_gone",
    "process_group",
]

T = TypeVar("T")
_PROC = Path("/proc")


@dataclass(frozen=True)
class ProcInfo:
    """One process as ``/proc/<pid>/stat`` shows it."""

    pid: int
    ppid: int
    pgid: int
    state: str  # R running, S sleeping, Z zombie, ...
    start: int  # start time in clock ticks after boot: with pid, the process's identity
    comm: str

    @property
    def dead(self) -> bool:
        return self.state in ("Z", "X", "x")


def proc_info(pid: int) -> ProcInfo | None:
    """The process ``pid`` now, or None if there is none."""
    try:
        text = (_PROC / str(pid) / "stat").read_text()
    except (FileNotFoundError, ProcessLookupError, PermissionError):
        return None
    head, _, rest = text.rpartition(")")  # comm may hold spaces and parentheses
    comm = head.split("(", 1)[1] if "(" in head else ""
    fields = rest.split()
    # fields[0] is field 3 of proc(5): state, ppid, pgrp, session, ... starttime is field 22.
    return ProcInfo(pid, int(fields[1]), int(fields[2]), fields[0], int(fields[19]), comm)


def all_processes() -> list[ProcInfo]:
    """Every process visible in ``/proc``."""
    out = []
    for entry in _PROC.iterdir():
        if entry.name.isdigit():
            info = proc_info(int(entry.name))
            if info is not None:
                out.append(info)
    return out


def group_members(pgid: int, exclude_leader: bool = False) -> list[ProcInfo]:
    """Live processes of process group ``pgid`` (zombies left out)."""
    return [p for p in all_processes()
            if p.pgid == pgid and not p.dead and not (exclude_leader and p.pid == pgid)]


def descendants(pid: int) -> list[ProcInfo]:
    """Live descendants of ``pid`` now (children, grandchildren, ...): a snapshot for :func:`survivors`."""
    procs = [p for p in all_processes() if not p.dead]
    children: dict[int, list[ProcInfo]] = {}
    for p in procs:
        children.setdefault(p.ppid, []).append(p)
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child.pid)
    return out


def alive(info: ProcInfo) -> bool:
    """Whether the very process of ``info`` (same pid and start time) still runs (a zombie does not)."""
    now = proc_info(info.pid)
    return now is not None and now.start == info.start and not now.dead


def survivors(snapshot: Sequence[ProcInfo]) -> list[ProcInfo]:
    """The processes of ``snapshot`` that still run."""
    return [p for p in snapshot if alive(p)]


def wait_for(predicate: Callable[[], T], timeout: float, what: str, interval: float = 0.05,
             proc: subprocess.Popen | None = None) -> T:
    """Poll ``predicate`` until it returns something truthy (returned); ``TimeoutError`` naming ``what``.

    With ``proc``, also fails as soon as ``proc`` has exited (it will not write anything more).
    """
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if proc is not None and proc.poll() is not None:
            raise RuntimeError(f"process {proc.pid} exited with {proc.returncode} before {what}")
        if time.monotonic() > deadline:
            raise TimeoutError(f"no {what} after {timeout:.0f} s")
        time.sleep(interval)


def wait_for_files(root: str | os.PathLike, pattern: str, count: int = 1, timeout: float = 60.0,
                   proc: subprocess.Popen | None = None) -> list[Path]:
    """Wait until ``root.glob(pattern)`` matches at least ``count`` files; returns them."""
    root = Path(root)

    def found() -> list[Path]:
        files = [p for p in root.glob(pattern) if p.is_file()]
        return files if len(files) >= count else []

    return wait_for(found, timeout, f"{count} file(s) {pattern} under {root}", proc=proc)


def start_in_new_group(cmd: Sequence[str], log: str | os.PathLike | None = None, **kwargs: Any) -> subprocess.Popen:
    """Start ``cmd`` as the leader of a new session / process group (its pid is the group id).

    Output goes to the file ``log`` (stdout and stderr together), or is discarded.
    """
    out: Any = open(log, "wb") if log is not None else subprocess.DEVNULL  # the child gets its own copy
    try:
        return subprocess.Popen(list(cmd), stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                start_new_session=True, **kwargs)
    finally:
        if log is not None:
            out.close()


def sigkill_leader(proc: subprocess.Popen, timeout: float = 10.0) -> int:
    """SIGKILL the group leader only (as the OOM killer or ``kill -9 <pid>`` would) and reap it."""
    proc.send_signal(signal.SIGKILL)
    return proc.wait(timeout)


def kill_group(pgid: int) -> None:
    """SIGKILL every process left in group ``pgid`` (test clean-up)."""
    try:
        os.killpg(pgid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def wait_until_gone(snapshot: Sequence[ProcInfo], timeout: float) -> list[ProcInfo]:
    """Wait up to ``timeout`` seconds for the processes of ``snapshot`` to end; returns those still running."""
    deadline = time.monotonic() + timeout
    while True:
        left = survivors(snapshot)
        if not left or time.monotonic() > deadline:
            return left
        time.sleep(0.05)


@contextmanager
def process_group(cmd: Sequence[str], log: str | os.PathLike | None = None,
                  **kwargs: Any) -> Iterator[subprocess.Popen]:
    """:func:`start_in_new_group`; on exit SIGKILL what is left of the group and reap the leader."""
    proc = start_in_new_group(cmd, log, **kwargs)
    try:
        yield proc
    finally:
        kill_group(proc.pid)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            pass
