"""The project's base class for mistakes in the user's input.

Ground floor: this module imports nothing from sdn3d, so every layer (data readers, edit specs,
scene files, weights, the command-line tools) can derive its user-facing errors from it.

The command-line tools (:mod:`sdn3d.cli._errors`) print a :class:`UserInputError` as one line,
``sdn3d-<tool>: error: <message>``, and exit with status 2. Any other exception is a bug or a
failure of the environment and keeps its traceback.
"""

from __future__ import annotations

__all__ = ["UserInputError", "InputError"]


class UserInputError(ValueError):
    """The user's input (a file, a setting, an edit) is wrong; the message names it and says what to do.

    The command-line tools print it without a traceback and exit 2. It is a :class:`ValueError`, so
    code that catches ``ValueError`` around a reader or a parser behaves as before.
    """


class InputError(UserInputError):
    """A bad command-line setting or input file of a tool (``sdn3d-edit``, ``sdn3d-bench``, ...)."""
