"""Errors raised by the dataset readers and the edit-spec parser.

Every message names the offending file (and line or entry where there is one) and
what is wrong with it, so a broken download or a hand-edited file can be fixed
without a debugger.
"""

from __future__ import annotations

import os

from sdn3d.errors import UserInputError

__all__ = ["DataFormatError", "MissingDataError", "missing"]


class DataFormatError(UserInputError):
    """A dataset or edit-spec file exists but does not follow its format."""


class MissingDataError(DataFormatError, FileNotFoundError):
    """A file or folder a reader needs is absent.

    Derives from both :class:`DataFormatError` and :class:`FileNotFoundError`, so
    callers may catch either: a missing file is a broken dataset layout as much
    as an OS-level absence.
    """


def missing(path: str | os.PathLike, what: str) -> MissingDataError:
    """A :class:`MissingDataError` for ``path`` saying which ``what`` was expected there."""
    return MissingDataError(f"{os.fspath(path)}: {what} not found")
