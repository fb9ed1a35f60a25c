"""Checkpoints that are never half-written: serialise, write a temp file, fsync, rename.

A process killed (SIGKILL, OOM, pre-emption) while a checkpoint is being written leaves the
previous ``last.ckpt`` intact; a full disk raises :class:`CheckpointWriteError` naming the file.
"""

from __future__ import annotations

import errno
import io
import logging
from pathlib import Path
from typing import Any

import torch
from lightning.fabric.plugins.io.torch_io import TorchCheckpointIO

from sdn3d.io import atomic_write

__all__ = ["AtomicCheckpointIO", "CheckpointWriteError"]

log = logging.getLogger(__name__)


class CheckpointWriteError(OSError):
    """A checkpoint could not be written (disk full, permission, missing directory)."""


class AtomicCheckpointIO(TorchCheckpointIO):
    """Lightning ``CheckpointIO`` writing local checkpoints atomically (temp file + ``os.replace``)."""

    def save_checkpoint(self, checkpoint: dict[str, Any], path: Any, storage_options: Any | None = None) -> None:
        if storage_options is not None:
            raise TypeError(f"{type(self).__name__} takes no storage_options, got {storage_options!r}")
        path = Path(path)
        # Serialise in memory first: a pickling error must not touch the directory at all.
        buffer = io.BytesIO()
        torch.save(checkpoint, buffer)
        try:
            atomic_write(path, lambda f: f.write(buffer.getbuffer()))
        except OSError as exc:
            reason = "the disk is full" if exc.errno == errno.ENOSPC else (exc.strerror or str(exc))
            raise CheckpointWriteError(
                exc.errno, f"could not write checkpoint {str(path)!r}: {reason}; the previous checkpoint "
                "(if any) is unchanged") from exc
        log.debug("wrote checkpoint %s (%d bytes)", path, buffer.getbuffer().nbytes)
