"""Errors raised by the dataset readers and the edit-spec parser, and the log of what a reader skipped.

Every message names the offending file (and line or entry where there is one) and
what is wrong with it, so a broken download or a hand-edited file can be fixed
without a debugger. :class:`DataFormatError` also carries that file as ``path`` (and the line as
``line``), so a training run can record which file stopped it.

:class:`SkipLog`: under ``fault.corrupt_sample=skip`` the readers do not raise on a bad frame or a bad
annotation row; they drop it and record it here (file, reason, the frame it belongs to).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field

from sdn3d.errors import UserInputError

__all__ = ["DataFormatError", "MissingDataError", "SkipLog", "SkippedItem", "missing", "path_in_message"]

# "<path>: ..." or "<path>:<line>: ..." at the start of a message; a path has a slash and either is absolute or
# has a file suffix (a frame key such as "vkitti1/0001/clone/00003" is not a file).
_LEADING_PATH = re.compile(r"^(?P<path>[^\s:][^:\n]*?)(?::(?P<line>\d+))?: ")


def path_in_message(message: str) -> tuple[str | None, int | None]:
    """``(path, line)`` named at the start of an error message, ``(None, None)`` when it names no file."""
    match = _LEADING_PATH.match(message)
    if match is None:
        return None, None
    path = match["path"]
    if "/" not in path and os.sep not in path:
        return None, None
    if not (os.path.isabs(path) or os.path.splitext(path)[1]):
        return None, None
    return path, int(match["line"]) if match["line"] else None


class DataFormatError(UserInputError):
    """A dataset or edit-spec file exists but does not follow its format.

    Attributes:
        path: the file at fault (from ``path=`` or the message's leading ``<path>:``); None when unknown.
        line: its line number where the message names one, else None.
    """

    def __init__(self, *args: object, path: str | os.PathLike | None = None, line: int | None = None) -> None:
        super().__init__(*args)
        found, found_line = path_in_message(str(args[0])) if args else (None, None)
        self.path: str | None = os.fspath(path) if path is not None else found
        self.line: int | None = line if line is not None else found_line


class MissingDataError(DataFormatError, FileNotFoundError):
    """A file or folder a reader needs is absent.

    Derives from both :class:`DataFormatError` and :class:`FileNotFoundError`, so
    callers may catch either: a missing file is a broken dataset layout as much
    as an OS-level absence.
    """


def missing(path: str | os.PathLike, what: str) -> MissingDataError:
    """A :class:`MissingDataError` for ``path`` saying which ``what`` was expected there."""
    return MissingDataError(f"{os.fspath(path)}: {what} not found", path=path)


@dataclass(frozen=True)
class SkippedItem:
    """One thing a reader dropped: ``kind`` ``'frame'`` (the whole frame) or ``'object'`` (one annotation row).

    ``frame`` is the :attr:`~sdn3d.data.records.FrameRecord.key` of the frame it belongs to (None when the
    row is too broken to say); ``path`` the file at fault (``'?'`` when unknown) and ``line`` its line;
    ``reason`` the error.
    """

    kind: str
    path: str
    reason: str
    frame: str | None = None
    line: int | None = None

    @property
    def where(self) -> str:
        """``file:line`` or ``file``."""
        return f"{self.path}:{self.line}" if self.line else self.path


@dataclass
class SkipLog:
    """What the readers skipped under ``fault.corrupt_sample=skip`` (see the module doc).

    A reader given a ``SkipLog`` calls :meth:`skip` instead of raising for a bad frame or a bad annotation
    row (quietly: the training run reports what was skipped, once). :func:`sdn3d.data.sources.load_split`
    keeps the items of one part and sets ``frames`` (how many frames that part has, skipped ones included),
    so :attr:`fraction` is the share of the part's frames that lost something.
    """

    items: list[SkippedItem] = field(default_factory=list)
    frames: int = 0

    def skip(self, exc: BaseException, kind: str, frame: str | None = None) -> None:
        """Record ``exc`` (a :class:`DataFormatError`, whose ``path`` names the file) for a dropped ``kind``."""
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        path = getattr(exc, "path", None) or getattr(exc, "filename", None) or "?"
        self.items.append(SkippedItem(kind, str(path), reason, frame, getattr(exc, "line", None)))

    def extend(self, items: list[SkippedItem]) -> None:
        self.items.extend(items)

    @property
    def skipped_frames(self) -> set[str]:
        """Keys of the frames dropped as a whole."""
        return {i.frame for i in self.items if i.kind == "frame" and i.frame is not None}

    @property
    def affected(self) -> int:
        """Frames that lost something (a whole frame or an object); an item without a frame counts once."""
        return len({i.frame for i in self.items if i.frame is not None}) + sum(i.frame is None for i in self.items)

    @property
    def fraction(self) -> float:
        """``affected / frames`` (0 when the part has no frames)."""
        return self.affected / self.frames if self.frames else 0.0

    @property
    def files(self) -> list[str]:
        """The files at fault (``file:line`` for a row), in the order they were met, each once."""
        return list(dict.fromkeys(i.where for i in self.items))
