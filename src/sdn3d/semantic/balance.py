"""Class weights for the cross-entropy from a training split's label histogram.

Rare, thin classes (poles, signs, traffic lights: well under 1 % of the synthetic pixels) get almost no
gradient from a plain pixel-averaged cross-entropy and end near 0 IoU. Two common remedies:

- ``median_frequency`` (SegNet, Eigen & Fergus): ``w_c = median(f) / f_c`` with ``f_c`` the pixel share of
  class ``c`` among the labelled pixels;
- ``enet`` (ENet, Paszke et al.): ``w_c = 1 / ln(1.02 + f_c)``.

Both are clipped to ``[0, max_weight]`` (a class seen on a handful of pixels would otherwise dominate), and
classes absent from the split get weight 0 (they have nothing to learn from).
"""

from __future__ import annotations

from collections.abc import Iterable

import torch
from torch import Tensor

from sdn3d.labels import IGNORE_INDEX

__all__ = ["CLASS_WEIGHTINGS", "label_histogram", "class_weights"]

CLASS_WEIGHTINGS = ("median_frequency", "enet")


def label_histogram(labels: Iterable[Tensor], num_classes: int) -> Tensor:
    """``(C,)`` int64 pixel counts of classes ``0..C-1`` over label maps (``IGNORE_INDEX`` and others skipped)."""
    counts = torch.zeros(num_classes, dtype=torch.int64)
    for label in labels:
        flat = label.reshape(-1).long()
        flat = flat[(flat >= 0) & (flat < num_classes) & (flat != IGNORE_INDEX)]
        counts += torch.bincount(flat, minlength=num_classes).cpu()
    return counts


def class_weights(counts: Tensor, method: str = "median_frequency", max_weight: float = 10.0) -> Tensor:
    """``(C,)`` float32 cross-entropy weights from pixel ``counts (C,)`` (see the module doc).

    Raises:
        ValueError: an unknown ``method``, ``max_weight <= 0``, or no labelled pixel at all.
    """
    if method not in CLASS_WEIGHTINGS:
        raise ValueError(f"class weighting must be one of {CLASS_WEIGHTINGS}, got {method!r}")
    if not max_weight > 0:
        raise ValueError(f"max_weight must be > 0, got {max_weight}")
    counts = counts.double()
    total = counts.sum()
    if total <= 0:
        raise ValueError("no labelled pixel: cannot weight the classes")
    freq = counts / total
    present = counts > 0
    if method == "median_frequency":
        weights = freq[present].median() / freq.clamp_min(1e-12)
    else:
        weights = 1.0 / torch.log(1.02 + freq)
    weights = torch.where(present, weights.clamp(max=max_weight), torch.zeros_like(weights))
    return weights.float()
