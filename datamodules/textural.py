"""Textural branch datamodule (thin: see :class:`sdn3d.data.datasets.TexturalDataset`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from torch.utils.data import DataLoader

from datamodules._base import BranchDataModule
from sdn3d.data.datasets import TexturalDataset
from sdn3d.data.errors import SkipLog
from sdn3d.data.sources import SourceConfig

__all__ = ["TexturalDataModule"]


class TexturalDataModule(BranchDataModule):
    """Frames with label / instance / boundary / normal / pose / depth maps.

    Args:
        data, image_size, batch_size, num_workers, seed, pin_memory, corrupt_sample, max_skipped_fraction: see
            :class:`BranchDataModule`.
        render: draw the ground-truth normal and pose maps (False leaves them zero).
    """

    def __init__(
        self,
        data: Mapping[str, Any] | SourceConfig,
        image_size: tuple[int, int] | list[int] | None = None,
        batch_size: int = 1,
        num_workers: int = 0,
        seed: int = 0,
        pin_memory: bool = False,
        render: bool = True,
        corrupt_sample: str = "fail",
        max_skipped_fraction: float = 0.1,
    ) -> None:
        super().__init__(data, image_size, batch_size, num_workers, seed, pin_memory, corrupt_sample,
                         max_skipped_fraction)
        self.render = bool(render)

    @property
    def classes(self):
        return self.source.class_list

    def make_dataset(self, part: str, skip: SkipLog | None = None) -> TexturalDataset:
        return TexturalDataset.from_source(self.source, part, skip, render=self.render)

    def code_bank_loader(self) -> DataLoader:
        """The training part in order, without geometry maps: the frames a code bank is encoded from
        (:meth:`lightning_modules.TexturalModule.on_fit_end`, :func:`sdn3d.textural.code_bank.build_code_bank`)."""
        dataset = TexturalDataset.from_source(self.source, "train", render=False)
        return DataLoader(dataset, batch_size=self.batch_size, shuffle=False, num_workers=0)
