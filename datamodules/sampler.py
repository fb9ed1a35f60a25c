"""The training loader's shuffling sampler, resumable: a resumed run sees the data order of a straight run.

``RandomSampler`` draws one permutation per epoch from the loader's seeded generator, which the
DataLoader also draws its base seed from; a resumed run used to start that generator from the seed again,
so it trained on the first epoch's order again. :class:`ResumableRandomSampler` draws exactly what
``RandomSampler`` draws (a run that is never resumed trains exactly as before) and keeps, for the
checkpoint, the generator's state before the current epoch's permutation, the generator's state now and how
many samples of the epoch were trained on. Restored, it puts the generator back, and if the run resumes in
the middle of that epoch, replays its permutation and skips what was already trained on.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator, Sized
from typing import Any

import torch
from torch.utils.data import RandomSampler

__all__ = ["ResumableRandomSampler"]


class ResumableRandomSampler(RandomSampler):
    """A ``RandomSampler`` (without replacement) whose position survives a checkpoint.

    Args:
        data_source: the dataset.
        generator: the seeded generator (the DataLoader's too, as with ``shuffle=True``).
        epoch_fn: the trainer's current epoch (None: count the epochs here); a restored state replays its
            epoch only when the run resumes in that same epoch.

    Attributes:
        consumed: samples of the current epoch trained on so far; the datamodule adds each training batch.
    """

    def __init__(self, data_source: Sized, generator: torch.Generator,
                 epoch_fn: Callable[[], int | None] | None = None) -> None:
        super().__init__(data_source, generator=generator)
        self.epoch_fn = epoch_fn
        self.epoch: int | None = None
        self.epoch_state: torch.Tensor | None = None
        self.consumed = 0
        self._epochs = 0
        self._resume: dict[str, Any] | None = None

    def _current_epoch(self) -> int:
        epoch = self.epoch_fn() if self.epoch_fn is not None else None
        return self._epochs if epoch is None else int(epoch)

    def __iter__(self) -> Iterator[int]:
        # A generator: this body runs at the first index, after the DataLoader drew its base seed.
        resume, self._resume = self._resume, None
        epoch = self._current_epoch()
        self._epochs += 1
        start = 0
        if resume is not None and resume.get("epoch") == epoch and int(resume.get("consumed", 0)) > 0:
            self.generator.set_state(resume["epoch_state"])  # this epoch's permutation again ...
            start = int(resume["consumed"])  # ... less what the checkpointed run trained on
        self.epoch, self.epoch_state, self.consumed = epoch, self.generator.get_state(), start
        yield from itertools.islice(super().__iter__(), start, None)

    def state_dict(self) -> dict[str, Any]:
        """Plain ints and byte tensors (loads with ``weights_only=True``); empty before the first epoch."""
        if self.epoch is None:
            return {}
        return {"epoch": int(self.epoch), "consumed": int(self.consumed), "epoch_state": self.epoch_state,
                "generator": self.generator.get_state()}

    def load_state_dict(self, state: dict[str, Any]) -> None:
        """Put the generator where the checkpointed run had it; the next epoch replays or goes on from there."""
        if not state:
            return
        self.generator.set_state(state["generator"])
        self._resume = dict(state)
