"""How every sdn3d command-line tool reports a mistake in the user's input: one line, exit status 2.

A user's mistake is

* a :class:`sdn3d.errors.UserInputError` (its subclasses name the file, setting or edit and say
  what to do: edit specs, dataset files, scene files, weights, summaries, CLI settings);
* an OS-level error about a path the user gave: :data:`PATH_ERRORS`;
* a configuration error of OmegaConf or Hydra (a bad override, a missing ``???`` value).

:func:`run_cli` prints it as ``sdn3d-<tool>: error: <message>`` on stderr and returns 2. Every other
exception (a plain ``ValueError`` included) is a bug or an environment failure: it propagates with
its traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from typing import Any

from sdn3d.errors import UserInputError

__all__ = ["EXIT_USER_ERROR", "PATH_ERRORS", "user_errors", "report_user_error", "run_cli", "exit_on_error"]

#: Exit status of a tool stopped by a user's mistake.
EXIT_USER_ERROR = 2
#: OS-level errors that, on the paths a tool is given, are the user's mistake.
PATH_ERRORS: tuple[type[OSError], ...] = (FileNotFoundError, FileExistsError, IsADirectoryError, NotADirectoryError,
                                          PermissionError)


def user_errors() -> tuple[type[BaseException], ...]:
    """The exception types :func:`run_cli` reports as a user's mistake (see the module doc)."""
    from hydra.errors import ConfigCompositionException, OverrideParseException
    from omegaconf.errors import OmegaConfBaseException

    return (UserInputError, *PATH_ERRORS, OmegaConfBaseException, ConfigCompositionException,
            OverrideParseException)


def report_user_error(tool: str, exc: BaseException) -> int:
    """Print ``sdn3d-<tool>: error: <exc>`` on stderr; returns :data:`EXIT_USER_ERROR`."""
    print(f"sdn3d-{tool}: error: {exc}", file=sys.stderr)
    return EXIT_USER_ERROR


def run_cli(tool: str, fn: Callable[..., int | None], *args: Any, **kwargs: Any) -> int:
    """Exit status of ``fn(*args, **kwargs)`` (None counts as 0), or 2 after reporting a user's mistake.

    Args:
        tool: the name after ``sdn3d-`` in the message (``edit``, ``bench``, ...).
        fn: the tool's work; other exceptions propagate unchanged.
    """
    from sdn3d.io import is_disk_full

    try:
        code = fn(*args, **kwargs)
    except user_errors() as exc:
        return report_user_error(tool, exc)
    except OSError as exc:  # a full disk is no bug: one line naming what could not be written, exit 1
        if not is_disk_full(exc):
            raise
        print(f"sdn3d-{tool}: error: {exc}" if "disk is full" in str(exc) else
              f"sdn3d-{tool}: error: the disk is full: {exc.strerror} ({exc.filename or 'a file'}); free some space "
              "and try again", file=sys.stderr)
        return 1
    return 0 if code is None else int(code)


def run_argparse_cli(tool: str, parser: argparse.ArgumentParser, fn: Callable[[argparse.Namespace], int | None],
                     argv: Sequence[str] | None = None) -> int:
    """:func:`run_cli` of ``fn(parser.parse_args(argv))`` for an argparse tool: ``--help`` and bad usage (argparse
    exits) give their exit status instead of raising, so ``main`` always returns an int."""
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    return run_cli(tool, fn, args)


def exit_on_error(code: int) -> None:
    """Inside a ``@hydra.main`` task: exit with ``code`` unless it is 0 (returning lets a multirun go on)."""
    if code:
        raise SystemExit(code)
