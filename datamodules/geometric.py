"""Geometric branch datamodule (thin: see :class:`sdn3d.data.datasets.GeometricDataset`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from datamodules._base import BranchDataModule
from sdn3d.data.datasets import GeometricDataset, ObjectFilter
from sdn3d.data.errors import SkipLog
from sdn3d.data.sources import SourceConfig
from sdn3d.math3d.encodings import AttributeEncoding

__all__ = ["GeometricDataModule"]


class GeometricDataModule(BranchDataModule):
    """Objects passing the paper's filter, as masked square crops with 3D targets.

    Args:
        data, image_size, batch_size, num_workers, seed, pin_memory, corrupt_sample, max_skipped_fraction: see
            :class:`BranchDataModule`.
        crop_size: side of the square object crops in pixels.
        margin: crop enlargement per side (fraction of the box's larger side).
        min_pixels, max_occlusion, max_truncation: the paper's filter thresholds.
        rotation, distance: target parameterisation (:class:`AttributeEncoding`; ablations).
        cache_items: keep decoded items in memory (:class:`GeometricDataset`).
        mirror: the training part also serves every object mirrored left to right (:class:`GeometricDataset`; twice
            the objects, issue 40); validation and test never.
    """

    sample_name = "objects passing the object filter (datamodule.min_pixels, max_occlusion, max_truncation)"

    def __init__(
        self,
        data: Mapping[str, Any] | SourceConfig,
        image_size: tuple[int, int] | list[int] | None = None,
        batch_size: int = 32,
        num_workers: int = 0,
        seed: int = 0,
        pin_memory: bool = False,
        crop_size: int = 64,
        margin: float = 0.1,
        min_pixels: int = 256,
        max_occlusion: float = 0.7,
        max_truncation: float = 0.7,
        rotation: str = "yaw_quaternion",
        distance: str = "log_tau",
        cache_items: bool = False,
        mirror: bool = False,
        corrupt_sample: str = "fail",
        max_skipped_fraction: float = 0.1,
    ) -> None:
        super().__init__(data, image_size, batch_size, num_workers, seed, pin_memory, corrupt_sample,
                         max_skipped_fraction)
        self.crop_size = int(crop_size)
        self.margin = float(margin)
        self.object_filter = ObjectFilter(int(min_pixels), float(max_occlusion), float(max_truncation))
        self.encoding = AttributeEncoding(rotation, distance)
        self.cache_items = bool(cache_items)
        self.mirror = bool(mirror)

    def make_dataset(self, part: str, skip: SkipLog | None = None) -> GeometricDataset:
        return GeometricDataset.from_source(self.source, part, skip, crop_size=self.crop_size, margin=self.margin,
                                            object_filter=self.object_filter, encoding=self.encoding,
                                            cache_items=self.cache_items, mirror=self.mirror and part == "train")
