"""What a corrupt sample does to a training run: stop naming the file, or report it and go on."""

from __future__ import annotations

import logging

from torch.utils.data import Dataset

from sdn3d.data.errors import DataFormatError

__all__ = ["CORRUPT_POLICIES", "CorruptSampleError", "SampleGuard"]

log = logging.getLogger(__name__)

CORRUPT_POLICIES = ("fail", "skip")


class CorruptSampleError(DataFormatError):
    """A sample could not be read and the policy is ``fail``."""


class SampleGuard(Dataset):
    """Wrap a dataset so unreadable samples follow ``policy``.

    ``fail`` re-raises as :class:`CorruptSampleError` with the dataset item and the file named
    by the reader. ``skip`` logs the file once and serves the next readable item instead, so
    batches keep their size; after ``max_skips`` consecutive failures it gives up (the data is
    broken, not one file).
    """

    def __init__(self, dataset: Dataset, policy: str = "fail", max_skips: int = 32) -> None:
        if policy not in CORRUPT_POLICIES:
            raise ValueError(f"fault.corrupt_sample must be one of {CORRUPT_POLICIES}, got {policy!r}")
        self.dataset = dataset
        self.policy = policy
        self.max_skips = int(max_skips)
        self.skipped: set[int] = set()

    def __len__(self) -> int:
        return len(self.dataset)  # type: ignore[arg-type]

    def __getattr__(self, name: str):
        # Datasets expose extras (classes, records, bank ...); keep them reachable through the guard.
        if name == "dataset":
            raise AttributeError(name)
        return getattr(self.dataset, name)

    def __getitem__(self, index: int):
        n = len(self)
        for attempt in range(min(self.max_skips, n) + 1):
            item = (index + attempt) % n
            try:
                return self.dataset[item]
            except DataFormatError as exc:
                if self.policy == "fail":
                    raise CorruptSampleError(
                        f"corrupt sample {item} of {type(self.dataset).__name__}: {exc} "
                        "(set fault.corrupt_sample=skip to skip such samples)") from exc
                if item not in self.skipped:
                    self.skipped.add(item)
                    log.warning("skipping corrupt sample %d: %s", item, exc)
        raise CorruptSampleError(f"{self.max_skips} consecutive unreadable samples from index {index} of "
                                 f"{type(self.dataset).__name__}; the dataset looks broken")
