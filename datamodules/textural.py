"""Textural branch datamodule (thin: see :class:`sdn3d.data.datasets.TexturalDataset`).

``maps`` picks the generator inputs: ``gt`` (the frames' ground-truth semantics, instances and
geometry: an oracle, a labelled ablation) or ``predicted`` (3D-SDN's: the trained semantic and
geometric branches' outputs, :mod:`sdn3d.predicted_maps`, computed once per part into
``map_cache_dir`` and reused while the checkpoints and the data are unchanged).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from torch.utils.data import DataLoader

from datamodules._base import BranchDataModule
from sdn3d.data.datasets import TexturalDataset
from sdn3d.data.errors import SkipLog
from sdn3d.data.map_cache import MapCache
from sdn3d.data.sources import SourceConfig, load_split
from sdn3d.errors import UserInputError

__all__ = ["TexturalDataModule", "MAP_SOURCES"]

log = logging.getLogger(__name__)

MAP_SOURCES = ("gt", "predicted")


class TexturalDataModule(BranchDataModule):
    """Frames with label / instance / boundary / normal / pose / depth maps.

    Args:
        data, image_size, batch_size, num_workers, seed, pin_memory, corrupt_sample, max_skipped_fraction: see
            :class:`BranchDataModule`.
        render: draw the ground-truth normal and pose maps (False leaves them zero; ``maps=gt`` only).
        maps: ``gt`` or ``predicted`` (module doc).
        semantic_checkpoint, geometric_checkpoint: the branches that predict the maps (``maps=predicted``).
        map_cache_dir: where predicted-map caches live (relative: to the working directory).
        refine_maps: refine the geometric predictions per image on L_reproj (the paper's Cityscapes setting,
            :class:`sdn3d.geometric.refine.RefineSettings` defaults); ``auto``: on for Cityscapes only.
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
        maps: str = "gt",
        semantic_checkpoint: str | None = None,
        geometric_checkpoint: str | None = None,
        map_cache_dir: str = "outputs/map_cache",
        refine_maps: bool | str = "auto",
    ) -> None:
        super().__init__(data, image_size, batch_size, num_workers, seed, pin_memory, corrupt_sample,
                         max_skipped_fraction)
        self.render = bool(render)
        if maps not in MAP_SOURCES:
            raise UserInputError(f"datamodule.maps must be one of {MAP_SOURCES}, got {maps!r}")
        if maps == "predicted":
            for name, path in (("semantic_checkpoint", semantic_checkpoint),
                               ("geometric_checkpoint", geometric_checkpoint)):
                if path is None:
                    raise UserInputError(
                        f"datamodule.maps=predicted needs datamodule.{name}=<the trained branch's checkpoint> "
                        "(3D-SDN trains the textural branch on the semantic and geometric branches' outputs); "
                        "or train on ground-truth maps with datamodule.maps=gt (an oracle ablation)")
                if not Path(path).expanduser().is_file():
                    raise UserInputError(f"datamodule.{name}: {path!r} does not exist")
        if refine_maps not in (True, False, "auto"):
            raise UserInputError(f"datamodule.refine_maps must be true, false or auto, got {refine_maps!r}")
        self.maps = maps
        self.semantic_checkpoint = semantic_checkpoint
        self.geometric_checkpoint = geometric_checkpoint
        self.map_cache_dir = Path(map_cache_dir).expanduser().resolve()
        self.refine_maps = self.source.kind == "cityscapes" if refine_maps == "auto" else bool(refine_maps)
        self._caches: dict[str, MapCache] = {}

    @property
    def classes(self):
        return self.source.class_list

    def predicted_maps(self, part: str, records) -> MapCache:
        """The predicted-map cache of ``part`` (built on first use)."""
        if part not in self._caches:
            from sdn3d.geometric.refine import RefineSettings
            from sdn3d.predicted_maps import build_predicted_maps

            self._caches[part] = build_predicted_maps(
                records, self.image_size, os.fspath(Path(self.semantic_checkpoint).expanduser()),
                os.fspath(Path(self.geometric_checkpoint).expanduser()), self.map_cache_dir, part,
                refine=RefineSettings() if self.refine_maps else None)
        return self._caches[part]

    def make_dataset(self, part: str, skip: SkipLog | None = None) -> TexturalDataset:
        if self.maps == "gt":
            return TexturalDataset.from_source(self.source, part, skip, render=self.render)
        records = load_split(self.source, part, skip)
        return TexturalDataset(records, self.image_size, self.classes, predicted=self.predicted_maps(part, records))

    def code_bank_loader(self) -> DataLoader:
        """The training part in order, without ground-truth geometry maps: the frames (and, with predicted maps,
        the predicted regions) a code bank is encoded from (:meth:`lightning_modules.TexturalModule.on_fit_end`,
        :func:`sdn3d.textural.code_bank.build_code_bank`)."""
        if self.maps == "gt":
            dataset = TexturalDataset.from_source(self.source, "train", render=False)
        else:
            dataset = self.make_dataset("train")
        return DataLoader(dataset, batch_size=self.batch_size, shuffle=False, num_workers=0)
