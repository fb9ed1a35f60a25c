"""Progress of a dataset generation on a text stream: frames done / total, frames per second, ETA.

On a terminal one line is rewritten in place (``\\r``, at most every ``interval_tty`` seconds); anywhere else
(a log file, a pipe, a CI job) a full line is written at most every ``interval_log`` seconds, so logs stay
short. The first frame and the last one are always reported; :meth:`FrameProgress.close` ends the line.

Example of a line: ``sdn3d-synth: 1234/21260 frames (5.8%), 8.41 frames/s, ETA 39m41s``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO

__all__ = ["FrameProgress", "format_duration"]


def format_duration(seconds: float) -> str:
    """``'7s'``, ``'3m05s'``, ``'2h04m'`` (whole seconds; hours drop the seconds)."""
    total = max(0, int(round(seconds)))
    hours, rest = divmod(total, 3600)
    minutes, secs = divmod(rest, 60)
    if hours:
        return f"{hours}h{minutes:02d}m"
    return f"{minutes}m{secs:02d}s" if minutes else f"{secs}s"


class FrameProgress:
    """Counts finished frames and reports them on ``stream``.

    Args:
        total: frames the run will render (regular frames and edit targets).
        stream: where to write (default ``sys.stderr``).
        label: line prefix.
        interval_tty, interval_log: least seconds between two reports on a terminal / elsewhere.
        clock: seconds, monotonic (tests pass a fake one).
    """

    def __init__(self, total: int, stream: TextIO | None = None, label: str = "sdn3d-synth",
                 interval_tty: float = 0.2, interval_log: float = 30.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.total = int(total)
        self.stream = sys.stderr if stream is None else stream
        self.label = label
        isatty = getattr(self.stream, "isatty", None)
        self.tty = bool(isatty()) if callable(isatty) else False
        self.interval = interval_tty if self.tty else interval_log
        self.clock = clock
        self.start = clock()
        self.done = 0
        self._last_report: float | None = None
        self._open_line = False

    def line(self) -> str:
        """The current report: frames done / total, percent, frames per second and ETA."""
        elapsed = max(self.clock() - self.start, 1e-9)
        rate = self.done / elapsed
        percent = 100.0 * self.done / self.total if self.total else 100.0
        if self.done >= self.total:
            tail = f"done in {format_duration(elapsed)}"
        elif self.done:
            tail = f"ETA {format_duration((self.total - self.done) / rate)}"
        else:
            tail = "ETA unknown"
        return f"{self.label}: {self.done}/{self.total} frames ({percent:.1f}%), {rate:.2f} frames/s, {tail}"

    def update(self, frames: int = 1) -> None:
        """``frames`` more frames are finished; report if the interval has passed (or at the first / last)."""
        self.done += int(frames)
        now = self.clock()
        due = self._last_report is None or now - self._last_report >= self.interval or self.done >= self.total
        if due:
            self._last_report = now
            self._write(self.line())

    def _write(self, text: str) -> None:
        if self.tty:
            self.stream.write("\r\x1b[2K" + text)
            self._open_line = True
        else:
            self.stream.write(text + "\n")
        self.stream.flush()

    def close(self) -> None:
        """End the in-place line on a terminal (nothing to do elsewhere)."""
        if self._open_line:
            self.stream.write("\n")
            self.stream.flush()
            self._open_line = False
