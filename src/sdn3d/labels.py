"""Class lists and instance-id arithmetic: the one place every layer takes them from.

- :class:`SemanticClass`: one entry of a class list (index, name, colour, has instances).
- The class lists by name (:data:`CLASS_LISTS`): ``'vkitti'`` (:data:`VKITTI_CLASSES`, the 14 classes
  of Virtual KITTI 1.3.1 / 2 and of the synthetic data) and ``'cityscapes'``
  (:data:`CITYSCAPES_TRAIN_CLASSES`, the 19 train ids); :func:`class_list` is the one lookup (by list
  name, by dataset kind, or a sequence checked in place).
- Instance ids: ``class_id * INSTANCE_DIVISOR + k`` (Cityscapes style, ``INSTANCE_DIVISOR`` = 1000),
  0 = no instance; a *region* id of an instance label map is an instance id (>= 1000) or a
  background class id (< 1000): :func:`region_class`.
- :data:`IGNORE_INDEX` (255): "no usable class" in semantic maps.

Example:
    >>> class_list("vkitti")[12].name, len(class_list("cityscapes"))
    ('Car', 19)
    >>> region_class(torch.tensor([5, 12003])).tolist()
    [5, 12]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

__all__ = [
    "IGNORE_INDEX",
    "INSTANCE_DIVISOR",
    "VEHICLE_CLASS_NAMES",
    "SemanticClass",
    "VKITTI_CLASSES",
    "VKITTI_CLASS_INDEX",
    "CITYSCAPES_EMBEDDED_LABELS",
    "CITYSCAPES_LABELS",
    "CITYSCAPES_TRAIN_CLASSES",
    "LABEL_TO_TRAIN",
    "CLASS_LISTS",
    "KIND_CLASS_LIST",
    "class_list",
    "thing_class_ids",
    "instance_ids",
    "split_instance_ids",
    "region_class",
]

#: Semantic label for "no usable class" (Cityscapes trainId convention).
IGNORE_INDEX = 255
#: Instance ids are ``class_id * INSTANCE_DIVISOR + k``.
INSTANCE_DIVISOR = 1000
#: Lower-case names of the classes, in every class list, whose objects are vehicles (the meshes' kind of object).
VEHICLE_CLASS_NAMES = ("car", "van", "truck", "bus", "train", "caravan", "trailer")

@dataclass(frozen=True)
class SemanticClass:
    """One entry of a dataset's class list: index ``id``, name, display colour."""

    id: int
    name: str
    color: tuple[int, int, int]
    has_instances: bool = False


# Colours of the Virtual KITTI 1.3.1 scene ground truth (README / encoding files).
# Car and Van have no class colour in VKITTI 1 (each track has its own colour);
# the colours given here are Virtual KITTI 2's, used for display only.
VKITTI_CLASSES: tuple[SemanticClass, ...] = tuple(
    SemanticClass(i, name, color, name in ("Car", "Van"))
    for i, (name, color) in enumerate(
        [
            ("Terrain", (210, 0, 200)),
            ("Sky", (90, 200, 255)),
            ("Tree", (0, 199, 0)),
            ("Vegetation", (90, 240, 0)),
            ("Building", (140, 140, 140)),
            ("Road", (100, 60, 100)),
            ("GuardRail", (255, 100, 255)),
            ("TrafficSign", (255, 255, 0)),
            ("TrafficLight", (200, 200, 0)),
            ("Pole", (255, 130, 0)),
            ("Misc", (80, 80, 80)),
            ("Truck", (160, 60, 60)),
            ("Car", (255, 127, 80)),
            ("Van", (0, 139, 139)),
        ]
    )
)
VKITTI_CLASS_INDEX = {c.name: c.id for c in VKITTI_CLASSES}

# (name, id, trainId, hasInstances, color) as in cityscapesscripts.helpers.labels.
CITYSCAPES_EMBEDDED_LABELS: tuple[tuple[str, int, int, bool, tuple[int, int, int]], ...] = (
    ("unlabeled", 0, 255, False, (0, 0, 0)),
    ("ego vehicle", 1, 255, False, (0, 0, 0)),
    ("rectification border", 2, 255, False, (0, 0, 0)),
    ("out of roi", 3, 255, False, (0, 0, 0)),
    ("static", 4, 255, False, (0, 0, 0)),
    ("dynamic", 5, 255, False, (111, 74, 0)),
    ("ground", 6, 255, False, (81, 0, 81)),
    ("road", 7, 0, False, (128, 64, 128)),
    ("sidewalk", 8, 1, False, (244, 35, 232)),
    ("parking", 9, 255, False, (250, 170, 160)),
    ("rail track", 10, 255, False, (230, 150, 140)),
    ("building", 11, 2, False, (70, 70, 70)),
    ("wall", 12, 3, False, (102, 102, 156)),
    ("fence", 13, 4, False, (190, 153, 153)),
    ("guard rail", 14, 255, False, (180, 165, 180)),
    ("bridge", 15, 255, False, (150, 100, 100)),
    ("tunnel", 16, 255, False, (150, 120, 90)),
    ("pole", 17, 5, False, (153, 153, 153)),
    ("polegroup", 18, 255, False, (153, 153, 153)),
    ("traffic light", 19, 6, False, (250, 170, 30)),
    ("traffic sign", 20, 7, False, (220, 220, 0)),
    ("vegetation", 21, 8, False, (107, 142, 35)),
    ("terrain", 22, 9, False, (152, 251, 152)),
    ("sky", 23, 10, False, (70, 130, 180)),
    ("person", 24, 11, True, (220, 20, 60)),
    ("rider", 25, 12, True, (255, 0, 0)),
    ("car", 26, 13, True, (0, 0, 142)),
    ("truck", 27, 14, True, (0, 0, 70)),
    ("bus", 28, 15, True, (0, 60, 100)),
    ("caravan", 29, 255, True, (0, 0, 90)),
    ("trailer", 30, 255, True, (0, 0, 110)),
    ("train", 31, 16, True, (0, 80, 100)),
    ("motorcycle", 32, 17, True, (0, 0, 230)),
    ("bicycle", 33, 18, True, (119, 11, 32)),
)


def _label_table() -> tuple[tuple[str, int, int, bool, tuple[int, int, int]], ...]:
    try:
        from cityscapesscripts.helpers.labels import labels
    except ImportError:
        return CITYSCAPES_EMBEDDED_LABELS
    rows = [
        (lb.name, lb.id, lb.trainId, bool(lb.hasInstances), tuple(lb.color)) for lb in labels if lb.id >= 0
    ]
    return tuple(sorted(rows, key=lambda r: r[1]))


#: The 34 label ids 0..33: ``(name, id, train_id, has_instances, color)``.
CITYSCAPES_LABELS = _label_table()
#: Label id -> train id (255 for ignored and for ids 34..255, which are rejected when read).
LABEL_TO_TRAIN = np.full(256, IGNORE_INDEX, dtype=np.int64)
for _name, _id, _train, _inst, _color in CITYSCAPES_LABELS:
    LABEL_TO_TRAIN[_id] = _train
#: The 19 training classes, indexed by train id.
CITYSCAPES_TRAIN_CLASSES: tuple[SemanticClass, ...] = tuple(
    SemanticClass(row[2], row[0], row[4], row[3])
    for row in sorted((r for r in CITYSCAPES_LABELS if r[2] != IGNORE_INDEX), key=lambda r: r[2])
)

#: Class lists by name (``classes:`` of ``conf/data/*.yaml``, ``SceneCode.classes``).
CLASS_LISTS: dict[str, tuple[SemanticClass, ...]] = {"vkitti": VKITTI_CLASSES, "cityscapes": CITYSCAPES_TRAIN_CLASSES}
#: Dataset kind (``SourceConfig.kind``) -> the name of its class list.
KIND_CLASS_LIST = {"vkitti1": "vkitti", "vkitti2": "vkitti", "cityscapes": "cityscapes"}


def class_list(classes: str | Sequence[SemanticClass]) -> tuple[SemanticClass, ...]:
    """The class list named ``classes`` (``'vkitti'`` (14), ``'cityscapes'`` (19 train ids) or a dataset
    kind such as ``'vkitti2'``), or ``classes`` itself, checked, when it already is a list of
    :class:`SemanticClass`."""
    if isinstance(classes, str):
        name = KIND_CLASS_LIST.get(classes, classes)
        if name not in CLASS_LISTS:
            raise ValueError(f"classes must name a class list ({sorted(CLASS_LISTS)}) or a dataset kind "
                             f"{tuple(KIND_CLASS_LIST)}, got {classes!r}")
        return CLASS_LISTS[name]
    out = tuple(classes)
    if not out or not all(isinstance(c, SemanticClass) for c in out):
        raise ValueError("classes must be a class-list name or a non-empty sequence of SemanticClass")
    if [c.id for c in out] != list(range(len(out))):
        raise ValueError(f"class ids must be 0..{len(out) - 1} in order, got {[c.id for c in out]}")
    return out


def thing_class_ids(classes: Sequence[SemanticClass], names: Sequence[str | int] | None = None) -> list[int]:
    """Ids of the classes split into instances: those with ``has_instances`` (``names`` None), else the
    listed class names or ids (e.g. ``['Car', 'Van']``)."""
    if names is None:
        return [c.id for c in classes if c.has_instances]
    by_name = {c.name: c.id for c in classes}
    out = []
    for n in names:
        if isinstance(n, str):
            if n not in by_name:
                raise ValueError(f"thing class {n!r} is not one of {sorted(by_name)}")
            out.append(by_name[n])
        elif 0 <= int(n) < len(classes):
            out.append(int(n))
        else:
            raise ValueError(f"thing class id {n} is outside 0..{len(classes) - 1}")
    return out


def instance_ids(class_ids: np.ndarray, k: np.ndarray) -> np.ndarray:
    """``class_id * 1000 + k`` as int64 (``k`` must lie in [0, 999])."""
    k = np.asarray(k, dtype=np.int64)
    if k.size and (k.min() < 0 or k.max() >= INSTANCE_DIVISOR):
        raise ValueError(
            f"instance_ids: k must lie in [0, {INSTANCE_DIVISOR - 1}], got [{k.min()}, {k.max()}]"
        )
    return np.asarray(class_ids, dtype=np.int64) * INSTANCE_DIVISOR + k


def split_instance_ids(ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`instance_ids`: ``(class_id, k)`` arrays."""
    ids = np.asarray(ids, dtype=np.int64)
    return ids // INSTANCE_DIVISOR, ids % INSTANCE_DIVISOR


def region_class(ids: Tensor) -> Tensor:
    """Semantic class of region ids: ``id // 1000`` for instances (>= 1000), the id itself otherwise."""
    return torch.where(ids >= INSTANCE_DIVISOR, torch.div(ids, INSTANCE_DIVISOR, rounding_mode="floor"), ids)
