"""What a corrupt sample does to a training run: stop naming the file, or report it and go on."""

from __future__ import annotations

import logging

from torch.utils.data import Dataset

from sdn3d.data.errors import DataFormatError

__all__ = ["CORRUPT_POLICIES", "SKIP_KEY", "CorruptSampleError", "SampleGuard", "TooMuchSkippedError"]

log = logging.getLogger(__name__)

CORRUPT_POLICIES = ("fail", "skip")
#: Key a skip-policy :class:`SampleGuard` adds to dict items: ``""``, or ``"<index>\t<file>\t<error>"`` for an item
#: served in place of an unreadable one. The datamodule takes it out of each batch (loader workers included) to
#: count what was skipped; models never see it.
SKIP_KEY = "_sdn3d_skipped"


class CorruptSampleError(DataFormatError):
    """A sample could not be read and the policy is ``fail`` (``path``: the file at fault)."""


class TooMuchSkippedError(CorruptSampleError):
    """More of the data was skipped than ``fault.max_skipped_fraction`` allows."""


class SampleGuard(Dataset):
    """Wrap a dataset so unreadable samples follow ``policy``.

    ``fail`` re-raises as :class:`CorruptSampleError` with the dataset item and the file named
    by the reader. ``skip`` logs the file once and serves the next readable item instead, so
    batches keep their size; after ``max_skips`` consecutive failures it gives up (the data is
    broken, not one file). Under ``skip``, dict items carry :data:`SKIP_KEY`, so the process that
    trains learns what a loader worker skipped.

    Attributes:
        skipped: indices skipped in this process; ``messages``: index -> ``"<file>\\t<error>"``.
    """

    def __init__(self, dataset: Dataset, policy: str = "fail", max_skips: int = 32) -> None:
        if policy not in CORRUPT_POLICIES:
            raise ValueError(f"fault.corrupt_sample must be one of {CORRUPT_POLICIES}, got {policy!r}")
        self.dataset = dataset
        self.policy = policy
        self.max_skips = int(max_skips)
        self.skipped: set[int] = set()
        self.messages: dict[int, str] = {}

    def __len__(self) -> int:
        return len(self.dataset)  # type: ignore[arg-type]

    def __getattr__(self, name: str):
        # Datasets expose extras (classes, records, bank ...); keep them reachable through the guard.
        if name == "dataset":
            raise AttributeError(name)
        return getattr(self.dataset, name)

    def __getitem__(self, index: int):
        n = len(self)
        note = ""
        for attempt in range(min(self.max_skips, n) + 1):
            item = (index + attempt) % n
            try:
                sample = self.dataset[item]
            except DataFormatError as exc:
                if self.policy == "fail":
                    raise CorruptSampleError(
                        f"corrupt sample {item} of {type(self.dataset).__name__}: {exc} "
                        "(set fault.corrupt_sample=skip to skip such samples)", path=exc.path) from exc
                reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
                if item not in self.skipped:
                    self.skipped.add(item)
                    self.messages[item] = f"{exc.path or '?'}\t{reason}"
                    log.warning("skipping corrupt sample %d: %s", item, exc)
                note = note or f"{item}\t{self.messages[item]}"
                continue
            if self.policy == "skip" and isinstance(sample, dict):
                sample = {**sample, SKIP_KEY: note}  # a copy: a dataset's cached item stays as it was
            return sample
        raise CorruptSampleError(f"{self.max_skips} consecutive unreadable samples from index {index} of "
                                 f"{type(self.dataset).__name__}; the dataset looks broken")
