"""Source configs: which dataset, where, which subsets, which split rule -> frame records.

A :class:`SourceConfig` mirrors one file of ``conf/data`` (plain fields, no ``_target_``):

- ``kind``: ``'vkitti1'`` (also the synthetic data, written in the VKITTI 1.3.1 format),
  ``'vkitti2'`` or ``'cityscapes'``.
- ``root``: dataset root folder.
- ``image_size``: working size ``(W, H)`` (paper: VKITTI 624x192, Cityscapes 512x256).
- ``subsets``: worlds (vkitti1), scenes (vkitti2) or cities (cityscapes); None = all.
- ``variations``: VKITTI variations; None = all (ignored for Cityscapes).
- ``camera``: VKITTI 2 camera (0 or 1).
- ``split``: the split rule, see :func:`split_records`.
- ``classes``: name of the class list (``'vkitti'`` or ``'cityscapes'``); checked against ``kind``.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from sdn3d.data import cityscapes, vkitti1, vkitti2
from sdn3d.data.errors import SkipLog
from sdn3d.data.records import FrameRecord
from sdn3d.data.vkitti1 import paper_split
from sdn3d.errors import UserInputError
from sdn3d.labels import CLASS_LISTS, KIND_CLASS_LIST, SemanticClass

__all__ = [
    "KINDS",
    "PARTS",
    "DEFAULT_IMAGE_SIZE",
    "SourceConfig",
    "read_source",
    "split_records",
    "load_split",
]

KINDS = ("vkitti1", "vkitti2", "cityscapes")
#: The parts a split rule yields (Lightning's fit/validate/test stages use them).
PARTS = ("train", "val", "test")
#: Paper working sizes ``(W, H)``.
DEFAULT_IMAGE_SIZE = {"vkitti1": (624, 192), "vkitti2": (624, 192), "cityscapes": (512, 256)}
# Default split rules. The paper has no validation split for Virtual KITTI: "val" reads the
# held-out 20% (the test part); Cityscapes' test labels are not public, so "test" reads "val".
_DEFAULT_SPLIT = {
    "vkitti1": {"rule": "paper", "fraction": 0.8, "first": True},
    "vkitti2": {"rule": "paper", "fraction": 0.8, "first": True},
    "cityscapes": {"rule": "folders", "train": "train", "val": "val", "test": "val"},
}


@dataclass(frozen=True)
class SourceConfig:
    """Where the frames come from; see the module doc for the fields."""

    kind: str
    root: str
    image_size: tuple[int, int] | None = None
    subsets: tuple[str, ...] | None = None
    variations: tuple[str, ...] | None = None
    camera: int = 0
    split: Mapping[str, Any] = field(default_factory=dict)
    classes: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise UserInputError(f"SourceConfig.kind must be one of {KINDS}, got {self.kind!r}")
        size = DEFAULT_IMAGE_SIZE[self.kind] if self.image_size is None else tuple(self.image_size)
        if len(size) != 2 or any(int(s) != s or s <= 0 for s in size):
            raise UserInputError(f"SourceConfig.image_size must be two positive integers [W, H], "
                                 f"got {self.image_size!r}")
        object.__setattr__(self, "image_size", (int(size[0]), int(size[1])))
        for name in ("subsets", "variations"):
            value = getattr(self, name)
            if isinstance(value, str):
                value = (value,)
            object.__setattr__(self, name, None if value is None else tuple(str(v) for v in value))
        split = {**_DEFAULT_SPLIT[self.kind], **dict(self.split or {})}
        _check_split(split, self.kind)
        object.__setattr__(self, "split", split)
        expected = KIND_CLASS_LIST[self.kind]
        if self.classes is not None and self.classes != expected:
            raise UserInputError(f"SourceConfig.classes must be {expected!r} for kind {self.kind!r}, "
                                 f"got {self.classes!r}")
        object.__setattr__(self, "classes", expected)

    @classmethod
    def from_mapping(cls, cfg: Mapping[str, Any] | SourceConfig) -> SourceConfig:
        """Build from a plain mapping or an OmegaConf ``DictConfig`` (unknown keys are an error)."""
        if isinstance(cfg, SourceConfig):
            return cfg
        if hasattr(cfg, "_metadata"):  # DictConfig: resolve interpolations, drop OmegaConf types
            from omegaconf import OmegaConf

            cfg = OmegaConf.to_container(cfg, resolve=True)
        if not isinstance(cfg, Mapping):
            raise UserInputError(f"data config must be a mapping, got {type(cfg).__name__}")
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(cfg) - known)
        if unknown:
            raise UserInputError(f"data config has unknown keys {unknown}; known keys are {sorted(known)}")
        return cls(**{k: v for k, v in cfg.items()})

    @property
    def class_list(self) -> tuple[SemanticClass, ...]:
        return CLASS_LISTS[self.classes]


def _check_split(split: Mapping[str, Any], kind: str) -> None:
    rule = split.get("rule")
    if rule == "paper":
        fraction = float(split.get("fraction", 0.8))
        if not 0.0 < fraction < 1.0:
            raise UserInputError(f"split.fraction must lie in (0, 1), got {fraction}")
        for part in ("val", "test"):
            if split.get(part, "test") not in ("train", "test"):
                raise UserInputError(f"split.{part} must name a paper-split part ('train' or 'test'), "
                                     f"got {split.get(part)!r}")
    elif rule == "folders":
        if kind != "cityscapes":
            raise UserInputError(f"split.rule 'folders' is only for cityscapes, got kind {kind!r}")
        for part in PARTS:
            if not isinstance(split.get(part), str):
                raise UserInputError(f"split.{part} must name a Cityscapes split folder, got {split.get(part)!r}")
    else:
        raise UserInputError(f"split.rule must be 'paper' or 'folders', got {rule!r}")


def read_source(source: SourceConfig, cityscapes_split: str = "train", skip: SkipLog | None = None
                ) -> list[FrameRecord]:
    """All frames of ``source`` (for Cityscapes: those of the folder ``cityscapes_split``).

    ``skip``: None raises on the first bad frame or annotation row; a :class:`SkipLog` records them (the
    readers' skip policy: Virtual KITTI still returns a skipped frame, :func:`load_split` drops it).
    """
    root = os.fspath(source.root)
    if source.kind == "vkitti1":
        return vkitti1.read_frames(root, worlds=source.subsets, variations=source.variations, skip=skip)
    if source.kind == "vkitti2":
        return vkitti2.read_frames(root, scenes=source.subsets, variations=source.variations,
                                   camera=source.camera, skip=skip)
    return cityscapes.read_frames(root, split=cityscapes_split, cities=source.subsets, skip=skip)


def split_records(records: Sequence[FrameRecord], split: Mapping[str, Any], part: str) -> list[FrameRecord]:
    """Apply a ``'paper'`` split rule to records.

    ``split = {rule: paper, fraction: 0.8, first: true, val: test, test: test}``: the first
    (``first``) ``floor(fraction * n)`` frames of each sequence are the train part, the rest
    the test part (:func:`~sdn3d.data.vkitti1.paper_split`); ``val`` and ``test`` name the
    paper part they read (default: the held-out one).
    """
    if part not in PARTS:
        raise ValueError(f"part must be one of {PARTS}, got {part!r}")
    if split.get("rule") != "paper":
        raise ValueError(f"split_records applies the 'paper' rule, got rule {split.get('rule')!r}")
    paper_part = "train" if part == "train" else str(split.get(part, "test"))
    return paper_split(records, paper_part, first=bool(split.get("first", True)),
                       fraction=float(split.get("fraction", 0.8)))


SYNTH_MANIFEST = "synth_manifest.json"


def edit_target_frames(root: str | os.PathLike) -> set[tuple[str, str, int]]:
    """``(world, variation, frame)`` of the edit-benchmark target frames a synthetic dataset appended to its
    sequences (``synth_manifest.json``); empty for any other dataset (real Virtual KITTI has none)."""
    path = Path(root) / SYNTH_MANIFEST
    if not path.is_file():
        return set()
    try:
        sequences = json.loads(path.read_text()).get("sequences") or []
        return {(str(s["world"]), str(s["variation"]), int(f)) for s in sequences
                for f in s.get("edit_target_frames") or []}
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise UserInputError(f"{str(path)!r}: cannot read the edit target frames: {exc}") from exc


def load_split(source: SourceConfig, part: str, skip: SkipLog | None = None) -> list[FrameRecord]:
    """Frame records of one part (``'train'``, ``'val'`` or ``'test'``) of ``source``.

    A synthetic dataset's edit-benchmark target frames (appended after each sequence's regular frames) are
    never trained on: the paper split is taken over the regular frames, so the benchmark's source frames
    (drawn from their last 20 %) are test frames, and the targets join the test part.

    ``skip``: None raises on the first bad frame or annotation row (naming the file). A :class:`SkipLog`
    gets what this part lost instead (its frames dropped, its objects' rows left out) and ``skip.frames``
    the part's frame count, skipped frames included; the split is taken before skipped frames are dropped,
    so a bad frame does not move the others between parts.
    """
    if part not in PARTS:
        raise ValueError(f"part must be one of {PARTS}, got {part!r}")
    found = None if skip is None else SkipLog()
    if source.split["rule"] == "folders":
        selected = read_source(source, cityscapes_split=source.split[part], skip=found)
    else:
        selected = _paper_part(source, part, found)
    if skip is None or found is None:
        return selected
    keys = {r.key for r in selected}
    folders = source.split["rule"] == "folders"  # every skipped frame of the folder is this part's
    mine = [i for i in found.items if i.frame is None or i.frame in keys or folders]
    dropped = {i.frame for i in mine if i.kind == "frame" and i.frame is not None}
    skip.extend(mine)
    skip.frames += len(keys | dropped)
    return [r for r in selected if r.key not in dropped]


def _paper_part(source: SourceConfig, part: str, skip: SkipLog | None) -> list[FrameRecord]:
    records = read_source(source, skip=skip)
    targets = edit_target_frames(source.root) if source.kind == "vkitti1" else set()
    if not targets:
        return split_records(records, source.split, part)
    is_target = [(r.world, r.variation, r.frame) in targets for r in records]
    regular = [r for r, t in zip(records, is_target, strict=True) if not t]
    selected = split_records(regular, source.split, part)
    paper_part = "train" if part == "train" else str(source.split.get(part, "test"))
    if paper_part == "test":
        selected += [r for r, t in zip(records, is_target, strict=True) if t]
    return selected
