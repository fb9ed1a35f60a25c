"""Checkpoints that are never half-written, never hold diverged weights, and never run code when loaded.

Saving: serialise, write a temp file, fsync, rename. A process killed (SIGKILL, OOM, pre-emption) while
a checkpoint is being written leaves the previous ``last.ckpt`` intact (and a stale temp file, which
:func:`sdn3d.training.rundir.remove_stale_temp_files` clears when the run starts or resumes); a full disk raises
:class:`CheckpointWriteError` naming the file. Weights holding NaN or infinity are refused
(:class:`NonFiniteCheckpointError`, naming the tensors): the previous checkpoint stays.

Loading (every Lightning load: ``trainer.fit(ckpt_path=...)``, resuming, ``trainer.test(ckpt_path=...)``):
``torch.load(weights_only=True)`` always, whatever the caller or ``TORCH_FORCE_NO_WEIGHTS_ONLY_LOAD`` ask
for, so a crafted checkpoint can not run code; one that needs more than tensors and plain containers is
refused with :class:`CheckpointLoadError`. Everything Lightning and the sdn3d modules store loads that
way (hyper-parameters are plain dicts and lists: ``lightning_modules._base.plain_hparams``; the loader's
place in the data order is ints and byte tensors: ``datamodules.sampler``).
"""

from __future__ import annotations

import errno
import io
import logging
import pickle
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import torch
from lightning.fabric.plugins.io.torch_io import TorchCheckpointIO
from lightning.pytorch.callbacks import ModelCheckpoint

from sdn3d.errors import UserInputError
from sdn3d.io import atomic_write, describe_load_failure

__all__ = ["AtomicCheckpointIO", "CheckpointLoadError", "CheckpointWriteError", "NonFiniteCheckpointError",
           "RunCheckpoint", "nonfinite_tensors"]

log = logging.getLogger(__name__)

class CheckpointWriteError(OSError):
    """A checkpoint could not be written (disk full, permission, missing directory); ``path``: the file."""


class NonFiniteCheckpointError(RuntimeError):
    """A checkpoint was refused because weights hold NaN or infinity (``path``: the file it would have been)."""


class CheckpointLoadError(UserInputError):
    """A checkpoint can not be loaded with ``torch.load(weights_only=True)`` (not a checkpoint, damaged, or
    holding objects other than tensors and plain containers); ``path``: the file."""


def nonfinite_tensors(state: Mapping[str, Any]) -> list[str]:
    """Names of the floating-point tensors of ``state`` (a state dict) that hold NaN or infinity."""
    return [name for name, value in state.items()
            if isinstance(value, torch.Tensor) and value.is_floating_point() and not bool(torch.isfinite(value).all())]


class AtomicCheckpointIO(TorchCheckpointIO):
    """Lightning ``CheckpointIO``: atomic local writes, finite weights only, ``weights_only=True`` loads.

    Args:
        relocate: ``{directory a checkpoint callback wrote to: the directory it writes to now}`` for a run resumed
            from another place (copied or moved): the paths a loaded checkpoint's ``ModelCheckpoint`` states record
            under an old directory (``dirpath``, ``best_model_path``, ``best_k_models``, ...) are taken from the new
            one, so the callback keeps its best-checkpoint selection and never names the old place's files.
    """

    def __init__(self, relocate: Mapping[str, str] | None = None) -> None:
        super().__init__()
        self.relocate = {str(k).rstrip("/"): str(v).rstrip("/") for k, v in (relocate or {}).items()}

    def _relocated(self, value: Any) -> Any:
        """``value`` (a callback state) with every path under a :attr:`relocate` directory moved to its new one."""
        if isinstance(value, Mapping):
            return {self._relocated(k): self._relocated(v) for k, v in value.items()}
        if isinstance(value, str):
            for old, new in self.relocate.items():
                if value == old or value.startswith(old + "/"):
                    return new + value[len(old):]
        return value

    def save_checkpoint(self, checkpoint: dict[str, Any], path: Any, storage_options: Any | None = None) -> None:
        if storage_options is not None:
            raise TypeError(f"{type(self).__name__} takes no storage_options, got {storage_options!r}")
        path = Path(path)
        bad = nonfinite_tensors(checkpoint.get("state_dict") or {})
        if bad:
            listed = ", ".join(bad[:8]) + (f" and {len(bad) - 8} more" if len(bad) > 8 else "")
            error = NonFiniteCheckpointError(
                f"refusing to write checkpoint {str(path)!r}: the weights hold NaN or infinity ({listed}); the "
                "previous checkpoint (if any) is kept")
            error.path = str(path)  # type: ignore[attr-defined]
            raise error
        # Serialise in memory first: a pickling error must not touch the directory at all.
        buffer = io.BytesIO()
        torch.save(checkpoint, buffer)
        try:
            atomic_write(path, lambda f: f.write(buffer.getbuffer()))
        except OSError as exc:
            reason = "the disk is full" if exc.errno == errno.ENOSPC else (exc.strerror or str(exc))
            error = CheckpointWriteError(
                exc.errno, f"could not write checkpoint {str(path)!r}: {reason}; the previous checkpoint "
                "(if any) is unchanged")
            error.path = str(path)  # type: ignore[attr-defined]
            raise error from exc
        log.debug("wrote checkpoint %s (%d bytes)", path, buffer.getbuffer().nbytes)

    def load_checkpoint(
        self,
        path: Any,
        map_location: Callable | None = lambda storage, loc: storage,
        weights_only: bool | None = None,
    ) -> dict[str, Any]:
        """``torch.load(path, weights_only=True)``; ``weights_only`` is accepted for Lightning's sake and ignored."""
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"Checkpoint file not found: {path}")
        try:
            with path.open("rb") as handle:
                checkpoint = torch.load(handle, map_location=map_location, weights_only=True)
        except pickle.UnpicklingError as exc:
            error = CheckpointLoadError(
                f"{path}: refused: it holds objects other than tensors and plain containers, which could run code "
                f"when loaded ({describe_load_failure(exc)})")
            error.path = str(path)  # type: ignore[attr-defined]
            raise error from exc
        except Exception as exc:  # whatever else unpickling a damaged file raises (IndexError, KeyError, ...)
            error = CheckpointLoadError(f"{path}: not a readable checkpoint ({describe_load_failure(exc)})")
            error.path = str(path)  # type: ignore[attr-defined]
            raise error from exc
        if not isinstance(checkpoint, dict):
            error = CheckpointLoadError(f"{path}: not a Lightning checkpoint (holds a {type(checkpoint).__name__})")
            error.path = str(path)  # type: ignore[attr-defined]
            raise error
        callbacks = checkpoint.get("callbacks")
        if self.relocate and isinstance(callbacks, dict):
            checkpoint["callbacks"] = {key: self._relocated(state) if isinstance(state, Mapping) and state.get(
                "dirpath") in self.relocate else state for key, state in callbacks.items()}
        return checkpoint


class RunCheckpoint(ModelCheckpoint):
    """``ModelCheckpoint`` whose ``last.ckpt`` (``save_last=True``) is written at every epoch's save point, whether or
    not the monitored metric improved.

    Lightning writes ``last.ckpt`` only when the same call wrote a top-k checkpoint: with ``monitor`` and
    ``save_top_k=1`` that is an improvement, so a run killed after it lost every epoch since. Its
    :attr:`state_key` is ``ModelCheckpoint``'s, so checkpoints of runs that used the plain callback resume with it
    and the other way round.
    """

    @property
    def state_key(self) -> str:
        key = super().state_key
        name = type(self).__qualname__
        return "ModelCheckpoint" + key[len(name):] if key.startswith(name) else key

    def on_train_epoch_end(self, trainer: Any, pl_module: Any) -> None:
        due = not self._should_skip_saving_checkpoint(trainer) and self._should_save_on_train_epoch_end(trainer)
        super().on_train_epoch_end(trainer, pl_module)
        if due:
            self._save_last_if_missed(trainer)

    def on_validation_end(self, trainer: Any, pl_module: Any) -> None:
        due = not self._should_skip_saving_checkpoint(trainer) and not self._should_save_on_train_epoch_end(trainer)
        super().on_validation_end(trainer, pl_module)
        if due:
            self._save_last_if_missed(trainer)

    def _save_last_if_missed(self, trainer: Any) -> None:
        if self.save_last and self._last_global_step_saved != trainer.global_step:
            self._save_last_checkpoint(trainer, self._monitor_candidates(trainer))
