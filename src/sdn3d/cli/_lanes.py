"""Stages run as child processes in a fixed number of *lanes* (``sdn3d-demo``'s ``lanes``).

Each lane runs its tasks one after another, in the order it was given them; a task starts once every task it
``needs`` (in any lane) has finished ok. Which lane runs which task is fixed by the caller, never by timing, and each
task is its own process with its own fixed thread count, so a task's result does not depend on what the other lane
does meanwhile (only the wall times do). The first task that fails stops the run: the other lanes' running children
are terminated and :class:`LaneError` names the failed task, its exit status, its log and the log's last line.
A SIGTERM to the runner (``kill``) or Ctrl-C stops the running children the same way before it exits.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading
import time
from collections.abc import Callable, Sequence
from contextlib import suppress
from pathlib import Path
from typing import Any, NamedTuple

#: Seconds between two looks at the running children.
POLL_S = 0.2


class LaneError(RuntimeError):
    """A lane's task failed (its child exited non-zero, or its result could not be read)."""


class LaneTask(NamedTuple):
    """One stage of a lane: a child process.

    ``start(done)`` launches it (``done``: the results of the tasks finished so far, by name); ``finish(code,
    done)`` turns its exit status into its result once it ended, and must raise (any exception) when it failed; it
    is called for a child that was stopped too (its clean-up), its error then ignored. ``log``: where the child
    writes its output."""

    name: str
    needs: tuple[str, ...]
    start: Callable[[dict[str, Any]], subprocess.Popen]
    finish: Callable[[int, dict[str, Any]], Any]
    log: Path


def check_plan(lanes: Sequence[Sequence[LaneTask]]) -> None:
    """Refuse a plan that cannot run to its end: a name twice, a need no task has, or a task that needs one placed
    after it in its own lane or one that (through the needs) waits for it.

    Raises:
        ValueError: naming the task.
    """
    names = [t.name for lane in lanes for t in lane]
    if len(set(names)) != len(names):
        raise ValueError(f"lane tasks named twice: {sorted(n for n in set(names) if names.count(n) > 1)}")
    missing = {n for lane in lanes for t in lane for n in t.needs if n not in names}
    if missing:
        raise ValueError(f"lane tasks need tasks no lane runs: {sorted(missing)}")
    # simulate: finished tasks in any order the lanes allow; a plan is sound if every task gets to run
    heads = [0] * len(lanes)
    done: set[str] = set()
    while True:
        ready = [i for i, lane in enumerate(lanes) if heads[i] < len(lane) and set(lane[heads[i]].needs) <= done]
        if not ready:
            break
        for i in ready:
            done.add(lanes[i][heads[i]].name)
            heads[i] += 1
    stuck = [lane[heads[i]].name for i, lane in enumerate(lanes) if heads[i] < len(lane)]
    if stuck:
        raise ValueError(f"lane tasks can never start (each waits for a task that waits for it): {stuck}")


def _last_line(log: Path) -> str:
    try:
        lines = [line.strip() for line in log.read_text(errors="replace").splitlines() if line.strip()]
    except OSError:
        return ""
    return lines[-1][:300] if lines else ""


def _exit_on_signal(signum: int, frame: Any) -> None:
    raise SystemExit(128 + signum)


def _ended(proc: subprocess.Popen) -> tuple[int | None, float | None]:
    """``(exit status, CPU seconds: user + system)`` of a child that ended, ``(None, None)`` while it runs. The CPU
    time (what the task costs on an idle machine with one thread, whatever the load) where the platform reports
    it (``os.wait4``), else None."""
    if not hasattr(os, "wait4") or proc.returncode is not None:
        return proc.poll(), None
    pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
    if pid == 0:
        return None, None
    proc.returncode = os.waitstatus_to_exitcode(status)
    return proc.returncode, round(usage.ru_utime + usage.ru_stime, 1)


def run_lanes(lanes: Sequence[Sequence[LaneTask]], clock_start: float | None = None,
              say: Callable[[str], None] = print) -> tuple[dict[str, Any], list[dict]]:
    """Run the lanes' tasks (module doc); returns ``({task name: its result}, timeline)``, the timeline one
    ``{'lane', 'task', 'start_s', 'end_s', 'wall_s', 'cpu_s'}`` per task, seconds since ``clock_start`` (default: now).

    Raises:
        LaneError: the first task that failed (the running ones stopped); ValueError: an unsound plan.
    """
    check_plan(lanes)
    # a `kill` of this process (SIGTERM) ends it through the clean-up below, not leaving the children running
    handler = signal.signal(signal.SIGTERM, _exit_on_signal) \
        if threading.current_thread() is threading.main_thread() else None
    origin = time.perf_counter() if clock_start is None else clock_start
    queues = [list(lane) for lane in lanes]
    running: dict[int, tuple[LaneTask, subprocess.Popen, float]] = {}
    done: dict[str, Any] = {}
    timeline: list[dict] = []
    try:
        while any(queues) or running:
            for i, queue in enumerate(queues):
                if i not in running and queue and all(n in done for n in queue[0].needs):
                    task = queue.pop(0)
                    say(f"lane {i + 1}: {task.name} started (output in {task.log})")
                    running[i] = (task, task.start(done), time.perf_counter())
            time.sleep(POLL_S)
            for i, (task, proc, started) in list(running.items()):
                code, cpu_s = _ended(proc)
                if code is None:
                    continue
                del running[i]
                ended = time.perf_counter()
                try:
                    done[task.name] = task.finish(code, done)
                except Exception as exc:
                    stopped = [t.name for t, _, _ in running.values()]
                    last = _last_line(task.log)
                    raise LaneError(f"{task.name} failed (exit {code}): {exc}; see {task.log}"
                                    + (f" (its last line: {last})" if last and last not in str(exc) else "")
                                    + (f"; stopped meanwhile: {', '.join(stopped)}" if stopped else "")) from exc
                timeline.append({"lane": i + 1, "task": task.name, "start_s": round(started - origin, 1),
                                 "end_s": round(ended - origin, 1), "wall_s": round(ended - started, 1),
                                 "cpu_s": cpu_s})
                say(f"lane {i + 1}: {task.name} finished ({ended - started:.0f} s)")
    finally:
        if handler is not None:
            signal.signal(signal.SIGTERM, handler)
        for task, proc, _ in running.values():  # a failure elsewhere, or an interrupt: stop, then clean up
            proc.terminate()
            with suppress(subprocess.TimeoutExpired):
                proc.wait(timeout=30)
            if proc.poll() is None:
                proc.kill()
            with suppress(Exception):
                task.finish(proc.wait(), done)
    return done, timeline
