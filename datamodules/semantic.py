"""Semantic branch datamodule (thin: see :class:`sdn3d.data.datasets.SemanticDataset`)."""

from __future__ import annotations

from typing import Any

from datamodules._base import BranchDataModule
from sdn3d.data.datasets import SemanticDataset
from sdn3d.data.errors import SkipLog

__all__ = ["SemanticDataModule"]


class SemanticDataModule(BranchDataModule):
    """Frames with semantic / instance maps at the working size; ``classes`` for logging.

    ``cache_items``: keep decoded frames in memory (:class:`SemanticDataset`); the other arguments are
    :class:`BranchDataModule`'s.
    """

    def __init__(self, *args: Any, cache_items: bool = False, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.cache_items = bool(cache_items)

    @property
    def classes(self):
        return self.source.class_list

    def make_dataset(self, part: str, skip: SkipLog | None = None) -> SemanticDataset:
        return SemanticDataset.from_source(self.source, part, skip, self.cache_items)
