"""Class statistics of a Virtual KITTI 1.3.1 tree: how much of each class the frames show, per world.

Computed from the written ``scenegt`` files through the reader (so they describe exactly what a training
run reads), for every frame and for the test part of the synthetic split (the paper's rule: the last 20 %
of each sequence's regular frames, plus the edit-benchmark target frames; :func:`sdn3d.data.sources.load_split`).

Per class and world:

- ``pixels``: labelled pixels (their share of all pixels is what the table prints);
- ``frames_with``: frames in which the class has at least one pixel;
- ``segments``: how many separate pieces of the class the frames show, summed over frames: for Car and
  Van the instance masks (one per visible track and frame), for every other class the 8-connected regions
  of at least :data:`MIN_SEGMENT_PIXELS` pixels (a pole occluded in the middle counts twice, two touching
  buildings once);
- ``tracks``: distinct Car / Van track ids seen (-1 for the other classes, which have no ids).

``sdn3d-synth`` prints :func:`format_table` and writes :data:`STATISTICS_NAME` into the dataset root.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import ndimage

from sdn3d.data import vkitti1
from sdn3d.data.errors import DataFormatError
from sdn3d.data.imageio import read_rgb
from sdn3d.data.records import FrameRecord
from sdn3d.data.sources import SourceConfig, load_split, read_source
from sdn3d.io import write_json_atomic
from sdn3d.labels import INSTANCE_DIVISOR, VKITTI_CLASSES

__all__ = [
    "STATISTICS_NAME",
    "PARTS",
    "MIN_SEGMENT_PIXELS",
    "ClassStatistics",
    "frame_class_counts",
    "class_statistics",
    "format_table",
    "shortfalls",
    "write_class_statistics",
    "read_class_statistics",
]

STATISTICS_NAME = "class_statistics.json"
#: ``all``: every frame; ``test``: the synthetic split's test part.
PARTS = ("all", "test")
#: Smallest connected region counted as a segment of a class without instance ids.
MIN_SEGMENT_PIXELS = 4
_NAMES = tuple(c.name for c in VKITTI_CLASSES)
_INSTANCE_CLASSES = tuple(c.id for c in VKITTI_CLASSES if c.has_instances)
# 8-connected regions within each class plane of a (C, H, W) stack, never across planes.
_PLANE_STRUCTURE = np.zeros((3, 3, 3), dtype=bool)
_PLANE_STRUCTURE[1] = True


@dataclass(frozen=True)
class ClassStatistics:
    """Per part (:data:`PARTS`), world and class counts of a dataset.

    Attributes:
        classes: ``(C,)`` class names (``labels.VKITTI_CLASSES`` order).
        worlds: ``(W,)`` world names.
        frames: ``(P, W)`` frames per part and world.
        image_pixels: ``(P, W)`` pixels of those frames.
        pixels: ``(P, W, C)`` labelled pixels.
        frames_with: ``(P, W, C)`` frames showing the class.
        segments: ``(P, W, C)`` instance masks (Car, Van) or connected regions (other classes), summed over frames.
        tracks: ``(P, W, C)`` distinct Car / Van tracks seen; -1 for the other classes.
    """

    classes: tuple[str, ...]
    worlds: tuple[str, ...]
    frames: np.ndarray
    image_pixels: np.ndarray
    pixels: np.ndarray
    frames_with: np.ndarray
    segments: np.ndarray
    tracks: np.ndarray

    def share(self, part: str) -> np.ndarray:
        """``(W + 1, C)`` pixel share in percent per world, the last row over all worlds."""
        p = PARTS.index(part)
        per_world = 100.0 * self.pixels[p] / np.maximum(self.image_pixels[p], 1)[:, None]
        total = 100.0 * self.pixels[p].sum(0) / max(int(self.image_pixels[p].sum()), 1)
        return np.concatenate([per_world, total[None]])

    def worlds_with(self, part: str) -> np.ndarray:
        """``(C,)`` how many worlds show each class in ``part``."""
        return (self.pixels[PARTS.index(part)] > 0).sum(0)

    @classmethod
    def from_dict(cls, data: dict) -> ClassStatistics:
        """The statistics back from :meth:`to_dict`'s mapping (``KeyError`` / ``TypeError`` if it is not one)."""
        classes, worlds = tuple(data["classes"]), tuple(data["worlds"])
        parts = [data["parts"][part] for part in PARTS]

        def table(key: str, default: int = 0) -> np.ndarray:
            return np.array([[[int(part["classes"][c]["per_world"][w].get(key, default)) for c in classes]
                              for w in worlds] for part in parts], dtype=np.int64)

        return cls(
            classes, worlds,
            frames=np.array([part["frames"] for part in parts], dtype=np.int64),
            image_pixels=np.array([part["image_pixels"] for part in parts], dtype=np.int64),
            pixels=table("pixels"), frames_with=table("frames_with_class"), segments=table("segments"),
            tracks=table("tracks", -1),
        )

    def to_dict(self) -> dict:
        out: dict = {"classes": list(self.classes), "worlds": list(self.worlds),
                     "min_segment_pixels": MIN_SEGMENT_PIXELS, "parts": {}}
        for p, part in enumerate(PARTS):
            share = self.share(part)
            out["parts"][part] = {
                "frames": self.frames[p].tolist(),
                "image_pixels": self.image_pixels[p].tolist(),
                "classes": {
                    name: {
                        "pixel_percent": round(float(share[-1, c]), 5),
                        "worlds_with_class": int(self.worlds_with(part)[c]),
                        "per_world": {
                            world: {
                                "pixels": int(self.pixels[p, w, c]),
                                "pixel_percent": round(float(share[w, c]), 5),
                                "frames_with_class": int(self.frames_with[p, w, c]),
                                "segments": int(self.segments[p, w, c]),
                                **({"tracks": int(self.tracks[p, w, c])} if self.tracks[p, w, c] >= 0 else {}),
                            }
                            for w, world in enumerate(self.worlds)
                        },
                    }
                    for c, name in enumerate(self.classes)
                },
            }
        return out


def frame_class_counts(semantic: np.ndarray, instances: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Counts of one frame.

    Args:
        semantic: ``(H, W)`` int64 class ids (``labels.VKITTI_CLASSES``).
        instances: ``(H, W)`` int64 instance ids ``class * 1000 + tid + 1`` (0: none).

    Returns:
        ``pixels (C,)``, ``segments (C,)`` (instance masks of Car / Van, connected regions of at least
        :data:`MIN_SEGMENT_PIXELS` pixels of the other classes) and the ``(K,)`` instance ids present.
    """
    num = len(VKITTI_CLASSES)
    pixels = np.bincount(semantic.ravel(), minlength=num)[:num]
    planes = semantic[None] == np.arange(num)[:, None, None]  # (C, H, W)
    labels, count = ndimage.label(planes, structure=_PLANE_STRUCTURE)
    sizes = np.bincount(labels.ravel(), minlength=count + 1)
    plane_of = np.zeros(count + 1, dtype=np.int64)
    plane_of[labels.ravel()] = np.repeat(np.arange(num), semantic.size)
    big = np.nonzero(sizes[1:] >= MIN_SEGMENT_PIXELS)[0] + 1
    segments = np.bincount(plane_of[big], minlength=num)
    ids = np.unique(instances[instances > 0])
    segments[list(_INSTANCE_CLASSES)] = np.bincount(ids // INSTANCE_DIVISOR, minlength=num)[list(_INSTANCE_CLASSES)]
    return pixels, segments, ids


def _scene_ground_truth(record: FrameRecord) -> tuple[np.ndarray, np.ndarray]:
    """``(semantic, instances)`` ``(H, W)`` int64 maps of a frame's scenegt image (one read, one decode)."""
    if record.semantic_path is None:
        raise DataFormatError(f"{record.key}: no scene ground truth on disk for this frame")
    encoding = vkitti1.parse_encoding(record.aux_path("encoding"))
    return encoding.decode(read_rgb(record.semantic_path), record.semantic_path)


def _records(root: Path) -> tuple[list[FrameRecord], set[str]]:
    """Every frame of the tree and the keys of its test part (the synthetic split: the paper's rule)."""
    source = SourceConfig(kind="vkitti1", root=os.fspath(root), split={"rule": "paper"})
    records = read_source(source)
    return records, {r.key for r in load_split(source, "test")}


def class_statistics(root: str | os.PathLike) -> ClassStatistics:
    """Class statistics of the Virtual KITTI 1.3.1 tree at ``root`` (every frame and the test part)."""
    records, test_keys = _records(Path(root))
    worlds = tuple(sorted({r.world for r in records}))
    num = len(VKITTI_CLASSES)
    shape = (len(PARTS), len(worlds), num)
    frames, image_pixels = np.zeros(shape[:2], np.int64), np.zeros(shape[:2], np.int64)
    pixels, frames_with, segments = (np.zeros(shape, np.int64) for _ in range(3))
    seen: dict[tuple[int, int], set[int]] = {}
    for record in records:
        semantic, instances = _scene_ground_truth(record)
        counts, pieces, ids = frame_class_counts(semantic, instances)
        w = worlds.index(record.world)
        for p in (0, 1) if record.key in test_keys else (0,):
            frames[p, w] += 1
            image_pixels[p, w] += semantic.size
            pixels[p, w] += counts
            frames_with[p, w] += counts > 0
            segments[p, w] += pieces
            seen.setdefault((p, w), set()).update(ids.tolist())
    tracks = np.full(shape, -1, np.int64)
    for c in _INSTANCE_CLASSES:
        tracks[:, :, c] = 0
    for (p, w), ids in seen.items():
        classes = np.array(sorted(ids), dtype=np.int64) // INSTANCE_DIVISOR
        for c in _INSTANCE_CLASSES:
            tracks[p, w, c] = int((classes == c).sum())
    return ClassStatistics(_NAMES, worlds, frames, image_pixels, pixels, frames_with, segments, tracks)


def format_table(stats: ClassStatistics, part: str) -> str:
    """A text table of one part: per class and world the pixel share (%) and the segments (see module doc)."""
    p = PARTS.index(part)
    share = stats.share(part)
    width = 16
    title = "every frame" if part == "all" else "test part (last 20 % of each sequence + edit targets)"
    lines = [
        f"class statistics, {title}: {int(stats.frames[p].sum())} frames; cells: pixel % / segments "
        f"(Car, Van: instance masks; others: regions >= {MIN_SEGMENT_PIXELS} px), summed over frames",
        f"{'class':<13}" + "".join(f"{w:>{width}}" for w in (*stats.worlds, "all")) + f"{'worlds':>8}",
    ]
    worlds_with = stats.worlds_with(part)
    for c, name in enumerate(stats.classes):
        cells = [f"{share[w, c]:8.3f} /{stats.segments[p, w, c]:5d}" for w in range(len(stats.worlds))]
        cells.append(f"{share[-1, c]:8.3f} /{stats.segments[p, :, c].sum():5d}")
        lines.append(f"{name:<13}" + "".join(f"{cell:>{width}}" for cell in cells) + f"{worlds_with[c]:>8d}")
    return "\n".join(lines)


def shortfalls(stats: ClassStatistics, part: str, min_percent: float, min_worlds: int) -> list[str]:
    """Classes below ``min_percent`` of the part's pixels or shown in fewer than ``min_worlds`` worlds."""
    share, worlds_with = stats.share(part)[-1], stats.worlds_with(part)
    return [
        f"{name}: {share[c]:.3f} % of the pixels, in {worlds_with[c]} world(s)"
        for c, name in enumerate(stats.classes)
        if share[c] < min_percent or worlds_with[c] < min_worlds
    ]


def write_class_statistics(root: str | os.PathLike) -> ClassStatistics:
    """Compute the statistics of the tree at ``root`` and write them to ``root / STATISTICS_NAME``."""
    stats = class_statistics(root)
    write_json_atomic(Path(root) / STATISTICS_NAME, stats.to_dict())
    return stats


def read_class_statistics(root: str | os.PathLike) -> ClassStatistics:
    """The statistics written by :func:`write_class_statistics` into the dataset at ``root``.

    Raises:
        DataFormatError: the file is missing or not such a table (the message names it).
    """
    path = Path(root) / STATISTICS_NAME
    try:
        return ClassStatistics.from_dict(json.loads(path.read_text()))
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise DataFormatError(f"{str(path)!r}: cannot read the class statistics: {exc}") from exc
