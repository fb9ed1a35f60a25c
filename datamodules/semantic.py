"""Semantic branch datamodule (thin: see :class:`sdn3d.data.datasets.SemanticDataset`)."""

from __future__ import annotations

from datamodules._base import BranchDataModule
from sdn3d.data.datasets import SemanticDataset
from sdn3d.data.errors import SkipLog

__all__ = ["SemanticDataModule"]


class SemanticDataModule(BranchDataModule):
    """Frames with semantic / instance maps at the working size; ``classes`` for logging."""

    @property
    def classes(self):
        return self.source.class_list

    def make_dataset(self, part: str, skip: SkipLog | None = None) -> SemanticDataset:
        return SemanticDataset.from_source(self.source, part, skip)
