"""Shared LightningDataModule plumbing: source config -> train/val/test datasets -> loaders.

All data logic lives in :mod:`sdn3d.data.datasets`; subclasses only say which dataset to build.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import lightning as L
import torch
from torch.utils.data import DataLoader, Dataset

from datamodules.guard import CORRUPT_POLICIES, SampleGuard
from sdn3d.data.sources import PARTS, SourceConfig

__all__ = ["BranchDataModule"]

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
        corrupt_sample: ``'fail'`` (stop, naming the file) or ``'skip'`` (report the file, use the next
            sample); ``sdn3d-train`` passes ``fault.corrupt_sample`` (conf/train.yaml).
    """

    def __init__(
        self,
        data: Mapping[str, Any] | SourceConfig,
        image_size: tuple[int, int] | list[int] | None = None,
        batch_size: int = 8,
        num_workers: int = 0,
        seed: int = 0,
        pin_memory: bool = False,
        corrupt_sample: str = "fail",
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
        self.datasets: dict[str, Dataset] = {}

    @property
    def image_size(self) -> tuple[int, int]:
        return self.source.image_size

    def make_dataset(self, part: str) -> Dataset:
        """The dataset of ``part`` (``'train'``, ``'val'`` or ``'test'``); subclasses override."""
        raise NotImplementedError

    def setup(self, stage: str | None = None) -> None:
        parts = PARTS if stage is None else _STAGE_PARTS.get(stage)
        if parts is None:
            raise ValueError(f"stage must be one of {sorted(_STAGE_PARTS)} or None, got {stage!r}")
        for part in parts:
            if part not in self.datasets:
                self.datasets[part] = SampleGuard(self.make_dataset(part), self.corrupt_sample)

    def _loader(self, part: str, shuffle: bool) -> DataLoader:
        if part not in self.datasets:  # loaders asked for without setup() (e.g. in notebooks)
            self.datasets[part] = SampleGuard(self.make_dataset(part), self.corrupt_sample)
        generator = torch.Generator().manual_seed(self.seed) if shuffle else None
        # Training drops a ragged last batch: a batch of one breaks BatchNorm (and skews its statistics);
        # never when that would leave no batch at all.
        ranks = self.trainer.world_size if self.trainer is not None else 1  # DDP splits the data first
        drop_last = shuffle and len(self.datasets[part]) // max(ranks, 1) > self.batch_size
        return DataLoader(
            self.datasets[part],
            batch_size=self.batch_size,
            shuffle=shuffle,
            num_workers=self.num_workers,
            pin_memory=self.pin_memory,
            generator=generator,
            drop_last=drop_last,
            persistent_workers=self.num_workers > 0,
        )

    def train_dataloader(self) -> DataLoader:
        return self._loader("train", shuffle=True)

    def val_dataloader(self) -> DataLoader:
        return self._loader("val", shuffle=False)

    def test_dataloader(self) -> DataLoader:
        return self._loader("test", shuffle=False)

    def predict_dataloader(self) -> DataLoader:
        return self._loader("test", shuffle=False)
