"""Split rules: which frames train, which validate, which test. Three disjoint parts for every dataset.

- :func:`paper_split`: the paper's per-sequence rule, the first (or last) ``floor(fraction * n)`` frames of
  each (world, variation) sequence train, the rest test.
- :func:`released_split`: the fixed per-world frame ranges of the paper's released code
  (:data:`RELEASED_RANGES`), which put all 92 pairs of the paper's editing benchmark in the test part.
  Virtual KITTI 2's ``SceneNN`` are the same worlds as Virtual KITTI 1's ``00NN``.
- Cityscapes: the dataset's own folders (``test`` = the official ``val`` folder; its test labels are not
  public); the folder rule lives in :mod:`sdn3d.data.sources`.

**Validation never reads the test part**: :func:`carve_validation` takes it out of the training frames, the
last ``val_fraction`` of each training range (grouped per (world, variation, camera); a Cityscapes city,
ordered by sequence and frame), and drops the ``val_gap`` training frames just before it so that
neighbouring frames, nearly the same picture, are not in both parts. A group too short to keep a training
frame, the gap and a validation frame gives all its frames to training.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence

from sdn3d.data.records import FrameRecord
from sdn3d.errors import UserInputError

__all__ = ["RELEASED_RANGES", "paper_split", "released_split", "released_world", "carve_validation"]

#: The released 3D-SDN code's split of Virtual KITTI: world -> ((first, last) train, (first, last) test)
#: frame indices, inclusive.
RELEASED_RANGES: Mapping[str, tuple[tuple[int, int], tuple[int, int]]] = {
    "0001": ((0, 355), (356, 446)),
    "0002": ((0, 184), (185, 232)),
    "0006": ((69, 269), (0, 68)),
    "0018": ((0, 269), (270, 338)),
    "0020": ((167, 836), (0, 166)),
}


def _sequence_key(record: FrameRecord) -> tuple:
    return (record.dataset, record.world, record.variation, record.camera, record.sequence)


def paper_split(
    frames: Sequence[FrameRecord], part: str = "train", first: bool = True, fraction: float = 0.8
) -> list[FrameRecord]:
    """The paper's per-sequence split: train on 80% of each world's frames, test on the rest.

    Frames are grouped by (dataset, world, variation, camera, sequence) and sorted by
    frame index; the training part holds ``floor(fraction * n)`` frames of each group.

    Args:
        frames: records to split.
        part: ``'train'`` or ``'test'``.
        first: True trains on the first 80% of each world and tests on the last 20%;
            False trains on the last 80% and tests on the first 20%. The paper says
            "first or last 80%" without fixing which; the released code's ranges
            (:func:`released_split`) do both, per world.
        fraction: training fraction in (0, 1).

    Returns:
        The selected records, grouped and in frame order.
    """
    if part not in ("train", "test"):
        raise ValueError(f"paper_split: part must be 'train' or 'test', got {part!r}")
    if not 0.0 < fraction < 1.0:
        raise ValueError(f"paper_split: fraction must lie in (0, 1), got {fraction}")
    groups: dict[tuple, list[FrameRecord]] = {}
    for record in frames:
        groups.setdefault(_sequence_key(record), []).append(record)
    selected: list[FrameRecord] = []
    for group in groups.values():
        group = sorted(group, key=lambda r: r.frame)
        n_train = math.floor(fraction * len(group) + 1e-9)
        n_first = n_train if first else len(group) - n_train
        head, tail = group[:n_first], group[n_first:]
        selected.extend(head if (part == "train") == first else tail)
    return selected


def released_world(world: str) -> str:
    """The :data:`RELEASED_RANGES` key of a Virtual KITTI 1 world (``'0006'``) or 2 scene (``'Scene06'``)."""
    match = re.fullmatch(r"(?:Scene)?0*(\d{1,4})", world)
    key = f"{int(match.group(1)):04d}" if match else world
    if key not in RELEASED_RANGES:
        raise UserInputError(f"split.rule 'released' knows the worlds {sorted(RELEASED_RANGES)} (Virtual KITTI 2: "
                             f"Scene01 ... Scene20), not {world!r}; use split.rule=paper for other data")
    return key


def released_split(frames: Sequence[FrameRecord], part: str = "train") -> list[FrameRecord]:
    """The released code's fixed per-world ranges (:data:`RELEASED_RANGES`); ``part``: ``'train'`` or ``'test'``.

    A tree that is not Virtual KITTI's is an error naming the frame or sequence: a frame outside both ranges
    of its world, or a sequence with no frame in one of them (e.g. synthetic data with short sequences, which
    would otherwise test on nothing). Returns the selected records grouped per sequence, in frame order.
    """
    if part not in ("train", "test"):
        raise ValueError(f"released_split: part must be 'train' or 'test', got {part!r}")
    groups: dict[tuple, list[FrameRecord]] = {}
    for record in sorted(frames, key=lambda r: (_sequence_key(r), r.frame)):
        groups.setdefault(_sequence_key(record), []).append(record)
    selected: list[FrameRecord] = []
    for group in groups.values():
        train, test = RELEASED_RANGES[released_world(group[0].world)]
        in_train = [train[0] <= r.frame <= train[1] for r in group]
        for record, a in zip(group, in_train, strict=True):
            if not a and not test[0] <= record.frame <= test[1]:
                raise UserInputError(f"{str(record.rgb_path)!r}: frame {record.frame} of world {record.world} is in "
                                     f"neither released range (train {train[0]}-{train[1]}, test {test[0]}-{test[1]});"
                                     f" use split.rule=paper for data other than Virtual KITTI")
        if all(in_train) or not any(in_train):
            where = "/".join(str(k) for k in _sequence_key(group[0])[1:] if k is not None)
            part = "training" if all(in_train) else "test"
            raise UserInputError(f"sequence {where} has frames {group[0].frame}-{group[-1].frame}, all in the released "
                                 f"{part} range of world {group[0].world}: it is not Virtual KITTI's sequence; use "
                                 f"split.rule=paper (as conf/data/synth.yaml does)")
        selected.extend(r for r, a in zip(group, in_train, strict=True) if a == (part == "train"))
    return selected


def carve_validation(train: Sequence[FrameRecord], fraction: float, gap: int
                     ) -> tuple[list[FrameRecord], list[FrameRecord]]:
    """Split training records into ``(train, val)`` (module doc): per group, the last
    ``max(1, round(fraction * n))`` frames validate and the ``gap`` frames before them belong to neither part.

    Groups: (dataset, world, variation, camera), ordered by (sequence, frame); a Cityscapes city is one group.
    A group of ``n < gap + 2`` frames stays in training whole.

    >>> from pathlib import Path
    >>> from sdn3d.math3d.camera import Intrinsics
    >>> k = Intrinsics(725.0, 725.0, 620.5, 187.0, 1242, 375)
    >>> frames = [FrameRecord("vkitti1", "0001", "clone", i, k, Path(f"{i}.png")) for i in range(20)]
    >>> train, val = carve_validation(frames, 0.1, 2)
    >>> [r.frame for r in train][-1], [r.frame for r in val]
    (15, [18, 19])
    """
    if not 0.0 < fraction < 1.0:
        raise UserInputError(f"split.val_fraction must lie in (0, 1), got {fraction}")
    if int(gap) != gap or gap < 0:
        raise UserInputError(f"split.val_gap must be a whole number of frames >= 0, got {gap}")
    groups: dict[tuple, list[FrameRecord]] = {}
    for record in train:
        groups.setdefault((record.dataset, record.world, record.variation, record.camera), []).append(record)
    kept: list[FrameRecord] = []
    val: list[FrameRecord] = []
    for group in groups.values():
        group = sorted(group, key=lambda r: (r.sequence or 0, r.frame))
        if len(group) < int(gap) + 2:
            kept.extend(group)
            continue
        n_val = min(max(1, round(fraction * len(group))), len(group) - int(gap) - 1)
        kept.extend(group[: len(group) - n_val - int(gap)])
        val.extend(group[len(group) - n_val:])
    return kept, val
