"""Class lists of the semantic branch by name, thing classes, and label-map colouring."""

from __future__ import annotations

from collections.abc import Sequence

import torch
from torch import Tensor

from sdn3d.data.datasets.sources import KINDS, classes_for
from sdn3d.data.records import IGNORE_INDEX, SemanticClass

__all__ = ["CLASS_LIST_NAMES", "resolve_classes", "thing_class_ids", "colorize_labels", "colorize_instances"]

#: Class-list names of ``conf/data/*.yaml`` (``classes:``) -> a dataset kind that uses the list.
CLASS_LIST_NAMES = {"vkitti": "vkitti1", "cityscapes": "cityscapes"}


def resolve_classes(classes: str | Sequence[SemanticClass]) -> tuple[SemanticClass, ...]:
    """The class list named ``classes`` (``'vkitti'`` (14), ``'cityscapes'`` (19 train ids) or a dataset
    kind such as ``'vkitti2'``), or ``classes`` itself when it already is a list of :class:`SemanticClass`."""
    if isinstance(classes, str):
        kind = CLASS_LIST_NAMES.get(classes, classes)
        if kind not in KINDS:
            raise ValueError(f"classes must name a class list ({sorted(CLASS_LIST_NAMES)}) or a dataset kind "
                             f"{KINDS}, got {classes!r}")
        return tuple(classes_for(kind))
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


def colorize_labels(label: Tensor, classes: Sequence[SemanticClass], ignore_index: int = IGNORE_INDEX) -> Tensor:
    """``(B, H, W)`` class indices -> ``(B, 3, H, W)`` float in [0, 1], in the dataset's colours
    (``ignore_index`` and out-of-range values black)."""
    palette = torch.zeros(len(classes) + 1, 3, device=label.device)
    palette[:-1] = torch.tensor([c.color for c in classes], dtype=torch.float32, device=label.device) / 255.0
    idx = torch.where((label >= 0) & (label < len(classes)) & (label != ignore_index), label,
                      torch.full_like(label, len(classes)))
    return palette[idx].permute(0, 3, 1, 2)


def colorize_instances(instance: Tensor) -> Tensor:
    """``(B, H, W)`` instance ids -> ``(B, 3, H, W)`` float in [0, 1]: a colour per id (a multiplicative
    hash of the id, so an id keeps its colour across images), black where the id is <= 0."""
    ids = instance.long().clamp_min(0)
    mult = torch.tensor([97, 57, 151], device=instance.device)
    rgb = ((ids.unsqueeze(1) * mult.view(1, 3, 1, 1) + 31) % 200 + 55).float() / 255.0
    return torch.where(ids.unsqueeze(1) > 0, rgb, torch.zeros_like(rgb))
