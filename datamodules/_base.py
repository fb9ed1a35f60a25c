"""Shared LightningDataModule plumbing: source config -> train/val/test datasets -> loaders.

All data logic lives in :mod:`sdn3d.data.datasets`; subclasses only say which dataset to build.

Faults (``fault.corrupt_sample``, ``fault.max_skipped_fraction`` in conf/train.yaml): under ``skip`` the
readers leave out bad frames and annotation rows while indexing (:class:`~sdn3d.data.errors.SkipLog`) and
:class:`~datamodules.guard.SampleGuard` serves the next sample for one that can not be read; each part stops
the run (:class:`~datamodules.guard.TooMuchSkippedError`) once more than ``max_skipped_fraction`` of it was
skipped, and :meth:`BranchDataModule.skip_summary` is what the run summary reports. An empty part is an
error naming the data root and the part.

The training loader shuffles with :class:`~datamodules.sampler.ResumableRandomSampler`, whose state the
checkpoint keeps (:meth:`BranchDataModule.state_dict`): a resumed run goes on with the data order of a
straight run.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import lightning as L
import torch
from torch.utils.data import DataLoader, Dataset

from datamodules.guard import CORRUPT_POLICIES, SKIP_KEY, SampleGuard, TooMuchSkippedError
from datamodules.sampler import ResumableRandomSampler
from sdn3d.data.errors import DataFormatError, SkipLog, SkippedItem
from sdn3d.data.sources import PARTS, SourceConfig

__all__ = ["BranchDataModule", "EmptyDataError"]

log = logging.getLogger(__name__)
# Lightning stage -> the part its batches come from (sanity checking validates).
_STAGE_PART = {"train": "train", "sanity_check": "val", "validate": "val", "test": "test", "predict": "test"}
_MAX_LISTED = 100  # files listed in the summary


class EmptyDataError(DataFormatError):
    """A part of the data has no samples (wrong root, subsets or split, or everything filtered out)."""

# Lightning stage -> parts it needs.
_STAGE_PARTS = {"fit": ("train", "val"), "validate": ("val",), "test": ("test",), "predict": ("test",)}


class BranchDataModule(L.LightningDataModule):
    """Base of the three branch datamodules.

    Args:
        data: the Hydra ``data`` group (mapping / DictConfig) or a :class:`SourceConfig`.
        image_size: working size ``[W, H]``; None keeps ``data.image_size`` (paper default per kind).
        batch_size: items per batch.
        num_workers: loader worker processes (default 0: CI machines have 2 cores).
        seed: seed of the training loader's shuffling generator.
        pin_memory: passed to the loaders.
        corrupt_sample: ``'fail'`` (stop, naming the file) or ``'skip'`` (report the file, leave out the frame
            or object while indexing, use the next sample while training); ``sdn3d-train`` passes
            ``fault.corrupt_sample`` (conf/train.yaml).
        max_skipped_fraction: under ``skip``, the share of a part's frames (while indexing) or samples
            (while training) that may be skipped before the run stops; ``fault.max_skipped_fraction``.
    """

    #: What one sample is, for the empty-data message.
    sample_name = "frames"

    def __init__(
        self,
        data: Mapping[str, Any] | SourceConfig,
        image_size: tuple[int, int] | list[int] | None = None,
        batch_size: int = 8,
        num_workers: int = 0,
        seed: int = 0,
        pin_memory: bool = False,
        corrupt_sample: str = "fail",
        max_skipped_fraction: float = 0.1,
    ) -> None:
        super().__init__()
        source = SourceConfig.from_mapping(data)
        if image_size is not None:
            source = replace(source, image_size=tuple(image_size))
        if batch_size <= 0:
            raise ValueError(f"batch_size must be positive, got {batch_size}")
        if num_workers < 0:
            raise ValueError(f"num_workers must be non-negative, got {num_workers}")
        self.source = source
        self.batch_size = int(batch_size)
        self.num_workers = int(num_workers)
        self.seed = int(seed)
        self.pin_memory = bool(pin_memory)
        if corrupt_sample not in CORRUPT_POLICIES:
            raise ValueError(f"corrupt_sample must be one of {CORRUPT_POLICIES}, got {corrupt_sample!r}")
        self.corrupt_sample = corrupt_sample
        if not 0.0 <= float(max_skipped_fraction) <= 1.0:
            raise ValueError(f"max_skipped_fraction must lie in [0, 1], got {max_skipped_fraction!r}")
        self.max_skipped_fraction = float(max_skipped_fraction)
        self.datasets: dict[str, Dataset] = {}
        self.skip_logs: dict[str, SkipLog] = {}  # part -> what indexing left out (skip policy)
        self.read_skips: dict[str, dict[int, str]] = {}  # part -> index -> "<file>\t<error>" (while training)
        self._reported: set[SkippedItem] = set()
        self.train_sampler: ResumableRandomSampler | None = None
        self._sampler_state: dict[str, Any] | None = None

    @property
    def image_size(self) -> tuple[int, int]:
        return self.source.image_size

    def make_dataset(self, part: str, skip: SkipLog | None = None) -> Dataset:
        """The dataset of ``part`` (``'train'``, ``'val'`` or ``'test'``); subclasses override.

        ``skip`` is None under the ``fail`` policy; under ``skip`` the readers record what they leave out there.
        """
        raise NotImplementedError

    def setup(self, stage: str | None = None) -> None:
        parts = PARTS if stage is None else _STAGE_PARTS.get(stage)
        if parts is None:
            raise ValueError(f"stage must be one of {sorted(_STAGE_PARTS)} or None, got {stage!r}")
        for part in parts:
            if part not in self.datasets:
                self.datasets[part] = self._guarded(part)

    def _describe(self, part: str) -> str:
        source = self.source
        subsets = f", subsets {list(source.subsets)}" if source.subsets else ""
        variations = f", variations {list(source.variations)}" if source.variations else ""
        return (f"the {part} part of the {source.kind} data at {str(source.root)!r} (split rule "
                f"{source.split['rule']!r}{subsets}{variations})")

    def _guarded(self, part: str) -> SampleGuard:
        skip = SkipLog() if self.corrupt_sample == "skip" else None
        dataset = self.make_dataset(part, skip)
        if skip is not None:
            self.skip_logs[part] = skip
            self._report(skip)
            if skip.fraction > self.max_skipped_fraction:
                raise TooMuchSkippedError(
                    f"{self._describe(part)}: {skip.affected} of its {skip.frames} frames lost data to unreadable "
                    f"or inconsistent files, more than fault.max_skipped_fraction={self.max_skipped_fraction:g}; "
                    f"first: {'; '.join(i.reason for i in skip.items[:3])}. Fix or remove those files (or raise "
                    "fault.max_skipped_fraction)", path=skip.items[0].path)
        if len(dataset) == 0:  # type: ignore[arg-type]
            raise EmptyDataError(
                f"{self._describe(part)} has no {self.sample_name}: check data.root, data.subsets / "
                "data.variations and data.split")
        return SampleGuard(dataset, self.corrupt_sample)

    def _report(self, skip: SkipLog) -> None:
        """Log each skipped frame / row once (the parts are indexed one by one and share unkeyed rows)."""
        new = [i for i in skip.items if i not in self._reported]
        self._reported.update(new)
        for item in new[:20]:
            log.warning("skipped %s%s: %s", item.kind, f" of {item.frame}" if item.frame else "", item.reason)
        if len(new) > 20:
            log.warning("... and %d more skipped frames / rows", len(new) - 20)

    def _loader(self, part: str, shuffle: bool) -> DataLoader:
        if part not in self.datasets:  # loaders asked for without setup() (e.g. in notebooks)
            self.datasets[part] = self._guarded(part)
        dataset = self.datasets[part]
        generator = torch.Generator().manual_seed(self.seed) if shuffle else None
        sampler = None
        if shuffle:  # what shuffle=True would draw, and resumable (module doc)
            sampler = ResumableRandomSampler(dataset, generator, self._trainer_epoch)  # type: ignore[arg-type]
            if self._sampler_state:
                sampler.load_state_dict(self._sampler_state)
                self._sampler_state = None
            if part == "train":
                self.train_sampler = sampler
        # Training drops a ragged last batch: a batch of one breaks BatchNorm (and skews its statistics);
        # never when that would leave no batch at all.
        ranks = self.trainer.world_size if self.trainer is not None else 1  # DDP splits the data first
        drop_last = shuffle and len(dataset) // max(ranks, 1) > self.batch_size  # type: ignore[arg-type]
        return DataLoader(
            dataset,
            batch_size=self.batch_size,
            sampler=sampler,
            num_workers=self.num_workers,
            pin_memory=self.pin_memory,
            generator=generator,
            drop_last=drop_last,
            persistent_workers=self.num_workers > 0,
        )

    def _trainer_epoch(self) -> int | None:
        return int(self.trainer.current_epoch) if self.trainer is not None else None

    # -- checkpoint: the training loader's place in the data order -------------------------------------------
    def state_dict(self) -> dict[str, Any]:
        state = self.train_sampler.state_dict() if self.train_sampler is not None else {}
        return {"train_sampler": state} if state else {}

    def load_state_dict(self, state_dict: dict[str, Any]) -> None:
        sampler_state = state_dict.get("train_sampler") or None
        if self.train_sampler is not None and sampler_state:
            self.train_sampler.load_state_dict(sampler_state)
        else:  # the loader is made later (Lightning restores before it asks for loaders)
            self._sampler_state = sampler_state

    # -- what the skip policy left out ----------------------------------------------------------------------
    def on_before_batch_transfer(self, batch: Any, dataloader_idx: int) -> Any:
        trainer = self.trainer
        stage = trainer.state.stage.value if trainer is not None and trainer.state.stage is not None else None
        part = _STAGE_PART.get(stage or "", "train")
        if isinstance(batch, dict) and SKIP_KEY in batch:
            batch = dict(batch)
            for note in batch.pop(SKIP_KEY):
                if note:
                    self._read_skip(part, note)
        if stage == "train" and self.train_sampler is not None:
            self.train_sampler.consumed += self.batch_size
        return batch

    def _read_skip(self, part: str, note: str) -> None:
        index, _, message = note.partition("\t")
        skips = self.read_skips.setdefault(part, {})
        if int(index) in skips:
            return
        skips[int(index)] = message
        total = len(self.datasets[part]) if part in self.datasets else 0  # type: ignore[arg-type]
        if total and len(skips) > self.max_skipped_fraction * total:
            path, _, reason = message.partition("\t")
            raise TooMuchSkippedError(
                f"{self._describe(part)}: {len(skips)} of its {total} samples could not be read, more than "
                f"fault.max_skipped_fraction={self.max_skipped_fraction:g}; latest: {path}: {reason}. Fix or "
                "remove those files (or raise fault.max_skipped_fraction)", path=path if path != "?" else None)

    def skip_summary(self) -> dict[str, Any]:
        """What the skip policy left out, for the run summary.

        ``skipped_samples``: frames that lost data while indexing (a whole frame or one object's row) plus
        samples skipped while reading, over all parts; ``skipped_fraction``: the largest share of one part;
        ``skipped_files``: the files at fault (``file`` or ``file:line``; at most 100).
        """
        frames: set[str] = set()
        unkeyed: set[SkippedItem] = set()
        files: dict[str, None] = {}
        fraction = 0.0
        for skip in self.skip_logs.values():
            for item in skip.items:
                (frames.add(item.frame) if item.frame is not None else unkeyed.add(item))
                files[item.where] = None
            fraction = max(fraction, skip.fraction)
        read = 0
        for part, dataset in self.datasets.items():
            messages = dict(self.read_skips.get(part, {}))
            messages.update({i: m for i, m in getattr(dataset, "messages", {}).items() if i not in messages})
            read += len(messages)
            for message in messages.values():
                files[message.partition("\t")[0]] = None
            if messages and len(dataset):  # type: ignore[arg-type]
                fraction = max(fraction, len(messages) / len(dataset))  # type: ignore[arg-type]
        return {"skipped_samples": len(frames) + len(unkeyed) + read, "skipped_fraction": round(fraction, 6),
                "skipped_files": list(files)[:_MAX_LISTED]}

    def train_dataloader(self) -> DataLoader:
        return self._loader("train", shuffle=True)

    def val_dataloader(self) -> DataLoader:
        return self._loader("val", shuffle=False)

    def test_dataloader(self) -> DataLoader:
        return self._loader("test", shuffle=False)

    def predict_dataloader(self) -> DataLoader:
        return self._loader("test", shuffle=False)
