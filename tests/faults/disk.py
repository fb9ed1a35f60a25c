"""A full disk: every file opened for writing through ``os.fdopen`` (how :func:`sdn3d.io.atomic_write` writes) takes
``room`` bytes, then raises ``OSError(ENOSPC)`` as a full file system does."""

from __future__ import annotations

import errno
import io
import os
from collections.abc import Iterator
from contextlib import contextmanager

import pytest


class _FullFile(io.RawIOBase):
    def __init__(self, handle, room: int) -> None:
        self._handle, self._room = handle, room

    def writable(self) -> bool:
        return True

    def write(self, data) -> int:
        size = len(memoryview(data))
        if size > self._room:
            raise OSError(errno.ENOSPC, "No space left on device")
        self._room -= size
        return self._handle.write(data)

    def fileno(self) -> int:
        return self._handle.fileno()

    def flush(self) -> None:
        if not self._handle.closed:
            self._handle.flush()

    def close(self) -> None:
        super().close()
        self._handle.close()


@contextmanager
def full_disk(room: int = 1024) -> Iterator[None]:
    """While the block runs, files opened for writing with ``os.fdopen`` hold at most ``room`` bytes each."""
    real = os.fdopen
    patch = pytest.MonkeyPatch()

    def fdopen(fd, mode="r", *args, **kwargs):
        handle = real(fd, mode, *args, **kwargs)
        return _FullFile(handle, room) if "w" in mode or "a" in mode else handle

    patch.setattr(os, "fdopen", fdopen)
    try:
        yield
    finally:
        patch.undo()
