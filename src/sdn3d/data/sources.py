"""Source configs: which dataset, where, which subsets, which split rule -> frame records.

A :class:`SourceConfig` mirrors one file of ``conf/data`` (plain fields, no ``_target_``):

- ``kind``: ``'vkitti1'`` (also the synthetic data, written in the VKITTI 1.3.1 format),
  ``'vkitti2'`` or ``'cityscapes'``.
- ``root``: dataset root folder.
- ``image_size``: working size ``(W, H)`` (paper: VKITTI 624x192, Cityscapes 512x256).
- ``subsets``: worlds (vkitti1), scenes (vkitti2) or cities (cityscapes); None = all.
- ``variations``: VKITTI variations; None = all (ignored for Cityscapes).
- ``camera``: VKITTI 2 camera (0 or 1).
- ``split``: the split rule and the validation carve, see :mod:`sdn3d.data.splits` and :func:`load_split`.
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
from sdn3d.data.splits import carve_validation, paper_split, released_split
from sdn3d.errors import UserInputError
from sdn3d.labels import CLASS_LISTS, KIND_CLASS_LIST, SemanticClass

__all__ = [
    "KINDS",
    "PARTS",
    "DEFAULT_IMAGE_SIZE",
    "SourceConfig",
    "read_source",
    "SPLIT_RULES",
    "split_records",
    "load_split",
]

KINDS = ("vkitti1", "vkitti2", "cityscapes")
#: The parts a split rule yields (Lightning's fit/validate/test stages use them).
PARTS = ("train", "val", "test")
#: Paper working sizes ``(W, H)``.
DEFAULT_IMAGE_SIZE = {"vkitti1": (624, 192), "vkitti2": (624, 192), "cityscapes": (512, 256)}
#: Split rules (:mod:`sdn3d.data.splits`) and the keys each takes.
SPLIT_RULES = {
    "paper": ("fraction", "first"),
    "released": (),
    "folders": ("train", "test"),
}
_VALIDATION_KEYS = ("val_fraction", "val_gap")
# Default split rules: Virtual KITTI 1 and 2 the released code's per-world ranges, Cityscapes its folders
# (the official "val" folder is the test part: the test labels are not public). Validation is always carved
# from the training frames (sdn3d.data.splits.carve_validation), never read from the test part.
_DEFAULT_SPLIT = {
    "vkitti1": {"rule": "released", "val_fraction": 0.1, "val_gap": 5},
    "vkitti2": {"rule": "released", "val_fraction": 0.1, "val_gap": 5},
    "cityscapes": {"rule": "folders", "train": "train", "test": "val", "val_fraction": 0.1, "val_gap": 1},
}
_RULE_DEFAULTS = {"paper": {"fraction": 0.8, "first": True}, "released": {}, "folders": {}}


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
        given = dict(self.split or {})
        defaults = _DEFAULT_SPLIT[self.kind]
        rule = given.get("rule", defaults["rule"])
        base = defaults if rule == defaults["rule"] else {k: defaults[k] for k in _VALIDATION_KEYS}
        split = {**base, **_RULE_DEFAULTS.get(rule, {}), **given, "rule": rule}
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
    if rule not in SPLIT_RULES:
        raise UserInputError(f"split.rule must be one of {sorted(SPLIT_RULES)}, got {rule!r}")
    if (rule == "folders") != (kind == "cityscapes"):
        raise UserInputError(f"split.rule {rule!r} is not for kind {kind!r}: Cityscapes splits by its folders, "
                             f"Virtual KITTI by 'released' (the released code's ranges) or 'paper'")
    for old in ("val", "test") if rule != "folders" else ("val",):
        if old in split:
            raise UserInputError(f"split.{old} is no longer a setting: validation is carved from the training "
                                 f"frames (split.val_fraction, split.val_gap) and never reads the test part")
    unknown = sorted(set(split) - {"rule", *SPLIT_RULES[rule], *_VALIDATION_KEYS})
    if unknown:
        raise UserInputError(f"split rule {rule!r} takes {sorted({'rule', *SPLIT_RULES[rule], *_VALIDATION_KEYS})}, "
                             f"not {unknown}")
    if rule == "paper" and not 0.0 < float(split["fraction"]) < 1.0:
        raise UserInputError(f"split.fraction must lie in (0, 1), got {split['fraction']}")
    if rule == "folders":
        for part in ("train", "test"):
            if not isinstance(split.get(part), str):
                raise UserInputError(f"split.{part} must name a Cityscapes split folder, got {split.get(part)!r}")
        if split["train"] == split["test"]:
            raise UserInputError(f"split.train and split.test name the same folder {split['train']!r}")
    if not 0.0 < float(split["val_fraction"]) < 1.0:
        raise UserInputError(f"split.val_fraction must lie in (0, 1), got {split['val_fraction']}")
    gap = split["val_gap"]
    if isinstance(gap, bool) or not isinstance(gap, int) or gap < 0:
        raise UserInputError(f"split.val_gap must be a whole number of frames >= 0, got {gap!r}")


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
    """Apply a Virtual KITTI split rule (``'paper'`` or ``'released'``) to records: one of the three parts.

    The rule gives train and test (:mod:`sdn3d.data.splits`); ``'val'`` is carved out of its training frames
    (``split.val_fraction``, ``split.val_gap``: :func:`~sdn3d.data.splits.carve_validation`), and ``'train'`` is
    what remains. The three parts are disjoint.
    """
    if part not in PARTS:
        raise ValueError(f"part must be one of {PARTS}, got {part!r}")
    rule = split.get("rule")
    if rule == "paper":
        def by_rule(p: str) -> list[FrameRecord]:
            return paper_split(records, p, first=bool(split.get("first", True)),
                               fraction=float(split.get("fraction", 0.8)))
    elif rule == "released":
        def by_rule(p: str) -> list[FrameRecord]:
            return released_split(records, p)
    else:
        raise ValueError(f"split_records applies the 'paper' or 'released' rule, got rule {rule!r}")
    if part == "test":
        return by_rule("test")
    train, val = carve_validation(by_rule("train"), float(split["val_fraction"]), int(split["val_gap"]))
    return train if part == "train" else val


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
    """Frame records of one part (``'train'``, ``'val'`` or ``'test'``) of ``source``; the parts are disjoint.

    Virtual KITTI: :func:`split_records` (the rule's train and test, validation carved from train). Cityscapes:
    ``test`` reads the folder ``split.test`` (the official ``val``), train and validation are carved from the
    folder ``split.train``. A synthetic dataset's edit-benchmark target frames (appended after each sequence's
    regular frames) are never trained or validated on: the rule runs over the regular frames, so the
    benchmark's source frames (drawn from their last 20 %) are test frames, and the targets join the test part.

    ``skip``: None raises on the first bad frame or annotation row (naming the file). A :class:`SkipLog`
    gets what this part lost instead (its frames dropped, its objects' rows left out) and ``skip.frames``
    the part's frame count, skipped frames included; the split is taken before skipped frames are dropped,
    so a bad frame does not move the others between parts. (Cityscapes drops a bad frame while reading: it
    counts for the train part of its folder, or the test part.)
    """
    if part not in PARTS:
        raise ValueError(f"part must be one of {PARTS}, got {part!r}")
    found = None if skip is None else SkipLog()
    folders = source.split["rule"] == "folders"
    if folders:
        folder = source.split["test" if part == "test" else "train"]
        selected = read_source(source, cityscapes_split=folder, skip=found)
        if part != "test":
            train, val = carve_validation(selected, float(source.split["val_fraction"]),
                                          int(source.split["val_gap"]))
            selected = train if part == "train" else val
    else:
        selected = _vkitti_part(source, part, found)
    if skip is None or found is None:
        return selected
    keys = {r.key for r in selected}
    # Cityscapes returns no record for a skipped frame: it belongs to the train (or test) part of its folder.
    mine = [i for i in found.items if i.frame is None or i.frame in keys or (folders and part != "val")]
    dropped = {i.frame for i in mine if i.kind == "frame" and i.frame is not None}
    skip.extend(mine)
    skip.frames += len(keys | dropped)
    return [r for r in selected if r.key not in dropped]


def _vkitti_part(source: SourceConfig, part: str, skip: SkipLog | None) -> list[FrameRecord]:
    records = read_source(source, skip=skip)
    targets = edit_target_frames(source.root) if source.kind == "vkitti1" else set()
    if not targets:
        return split_records(records, source.split, part)
    is_target = [(r.world, r.variation, r.frame) in targets for r in records]
    regular = [r for r, t in zip(records, is_target, strict=True) if not t]
    selected = split_records(regular, source.split, part)
    if part == "test":
        selected += [r for r, t in zip(records, is_target, strict=True) if t]
    return selected
