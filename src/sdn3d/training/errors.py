"""The errors of a training run and their one-line prose (what a run's summary records as ``error`` and
``error_file``)."""

from __future__ import annotations

import os
import re

from sdn3d.errors import UserInputError

__all__ = ["RunFailedError", "TrainingError", "error_file", "error_sentence"]


class TrainingError(UserInputError, RuntimeError):
    """A run could not start or stopped for a reason the user can act on (message says which)."""


class RunFailedError(TrainingError):
    """A run started and ended with status ``failed`` (e.g. a non-finite loss); its summary says why.
    ``sdn3d-train`` prints it in one line and exits 1."""


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

