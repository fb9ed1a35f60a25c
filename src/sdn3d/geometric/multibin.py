"""MultiBin orientation (Mousavian et al., "3D Bounding Box Estimation Using Deep Learning and Geometry",
CVPR 2017, Sec. 3.3): an angle as a choice among overlapping bins plus a residual inside the chosen bin.

``B`` bins with centres ``c_i = wrap(2 pi i / B)`` each cover the angles within ``(pi / B) (1 + overlap)``
of their centre, so neighbouring bins overlap by ``2 pi overlap / B`` and every angle is covered by one or
two bins. Per bin the network predicts a confidence logit and a residual ``(cos theta_i, sin theta_i)``
(L2-normalised). Losses, per object:

- ``conf``: softmax cross-entropy of the logits against the covering bins (a uniform distribution over
  them: with two covering bins, half each);
- ``loc``: ``mean over covering bins i of 1 - cos(theta - c_i - theta_i)``: the paper's
  ``-cos(theta - c_i - theta_i)`` shifted by 1 so that a perfect residual costs 0 (same gradients).

Decoding takes the most confident bin: ``theta = wrap(c_i + atan2(sin theta_i, cos theta_i))``.
Everything is batched over objects and bins; angles are radians, wrapped to ``[-pi, pi)``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.math3d.rotations import wrap_angle

__all__ = [
    "MultiBinTarget",
    "bin_centers",
    "bin_half_width",
    "normalize_residual",
    "encode_multibin",
    "decode_multibin",
    "multibin_losses",
]

_EPS = 1e-6


class MultiBinTarget(NamedTuple):
    """MultiBin encoding of ``N`` angles over ``B`` bins.

    Attributes:
        cover: ``(N, B)`` bool, the bins whose range holds the angle (one or two per angle).
        residual: ``(N, B)`` ``wrap(angle - c_i)``, the angle relative to each bin centre (radians).
    """

    cover: Tensor
    residual: Tensor


def _check_bins(num_bins: int, overlap: float) -> None:
    if int(num_bins) != num_bins or num_bins < 1:
        raise ValueError(f"num_bins must be a positive integer, got {num_bins!r}")
    if not 0.0 <= float(overlap) < 1.0:
        raise ValueError(f"overlap must lie in [0, 1) (a fraction of half a bin), got {overlap!r}")


def bin_centers(num_bins: int, device: torch.device | str | None = None,
                dtype: torch.dtype = torch.float32) -> Tensor:
    """``(B,)`` bin centres ``wrap(2 pi i / B)``, ``i = 0 .. B-1`` (two bins: ``0`` and ``-pi``)."""
    _check_bins(num_bins, 0.0)
    return wrap_angle(torch.arange(num_bins, device=device, dtype=dtype) * (2 * math.pi / num_bins))


def bin_half_width(num_bins: int, overlap: float) -> float:
    """Half the angular range a bin covers: ``(pi / B) (1 + overlap)`` radians."""
    _check_bins(num_bins, overlap)
    return math.pi / num_bins * (1.0 + float(overlap))


def normalize_residual(residual: Tensor) -> Tensor:
    """``(N, B, 2)`` raw ``(cos, sin)`` outputs -> unit vectors (differentiable; zero vectors stay finite)."""
    if residual.dim() != 3 or residual.shape[-1] != 2:
        raise ValueError(f"residual must have shape (N, B, 2) as (cos, sin), got {tuple(residual.shape)}")
    return F.normalize(residual, dim=-1, eps=_EPS)


def encode_multibin(angle: Tensor, num_bins: int, overlap: float) -> MultiBinTarget:
    """Covering bins and per-bin residuals of ``(N,)`` angles (radians, any range)."""
    if angle.dim() != 1:
        raise ValueError(f"angle must have shape (N,), got {tuple(angle.shape)}")
    half = bin_half_width(num_bins, overlap)
    residual = wrap_angle(angle.unsqueeze(1) - bin_centers(num_bins, angle.device, angle.dtype))  # (N, B)
    # The nearest bin is at most pi / B away, inside its range: every angle has a covering bin.
    cover = residual.abs() <= half
    return MultiBinTarget(cover, residual)


def decode_multibin(conf_logits: Tensor, residual: Tensor) -> Tensor:
    """``(N,)`` angles in ``[-pi, pi)`` from ``(N, B)`` confidence logits and ``(N, B, 2)`` ``(cos, sin)`` residuals.

    The most confident bin's centre plus its residual angle; the residual need not be normalised.
    """
    if conf_logits.dim() != 2 or residual.shape != (*conf_logits.shape, 2):
        raise ValueError(f"conf_logits must be (N, B) and residual (N, B, 2), got {tuple(conf_logits.shape)} "
                         f"and {tuple(residual.shape)}")
    best = conf_logits.argmax(dim=1)  # (N,)
    picked = residual[torch.arange(residual.shape[0], device=residual.device), best]  # (N, 2)
    centers = bin_centers(conf_logits.shape[1], conf_logits.device, residual.dtype)
    return wrap_angle(centers[best] + torch.atan2(picked[:, 1], picked[:, 0]))


def multibin_losses(conf_logits: Tensor, residual: Tensor, angle: Tensor, overlap: float) -> dict[str, Tensor]:
    """Per-object MultiBin losses (see the module doc), differentiable w.r.t. the logits and the raw residuals.

    Args:
        conf_logits: ``(N, B)`` bin confidence logits.
        residual: ``(N, B, 2)`` raw ``(cos, sin)`` residual outputs (normalised here).
        angle: ``(N,)`` target angles (radians).
        overlap: bin overlap of the encoding (:func:`bin_half_width`).

    Returns:
        ``conf (N,)`` cross-entropy against the covering bins and ``loc (N,)`` mean ``1 - cos`` residual error
        over them (in ``[0, 2]``).
    """
    if conf_logits.dim() != 2 or residual.shape != (*conf_logits.shape, 2) or angle.shape != conf_logits.shape[:1]:
        raise ValueError(f"need conf_logits (N, B), residual (N, B, 2) and angle (N,), got "
                         f"{tuple(conf_logits.shape)}, {tuple(residual.shape)} and {tuple(angle.shape)}")
    target = encode_multibin(angle.to(residual.dtype), conf_logits.shape[1], overlap)
    weight = target.cover.to(residual.dtype)
    weight = weight / weight.sum(dim=1, keepdim=True)  # (N, B): uniform over the covering bins
    conf = -(weight * conf_logits.log_softmax(dim=1)).sum(dim=1)
    unit = normalize_residual(residual)
    cos_err = target.residual.cos() * unit[..., 0] + target.residual.sin() * unit[..., 1]  # cos(d - theta_i)
    loc = (weight * (1.0 - cos_err)).sum(dim=1)
    return {"conf": conf, "loc": loc}
