"""Rotations about the camera y axis and the observation angle (KITTI conventions)."""

from __future__ import annotations

import math

import torch
from torch import Tensor

__all__ = ["roty", "wrap_angle", "observation_angle", "alpha_bins", "NUM_POSE_BINS"]

#: The pose map quantises the observation angle into this many bins over [-pi, pi).
NUM_POSE_BINS = 24


def roty(ry: Tensor) -> Tensor:
    """Rotation about the camera y axis (KITTI devkit ``roty``).

    ``R = [[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]]``; ``ry = 0`` keeps the canonical
    +x (vehicle front) along the camera +x axis.

    The values are those of kornia's ``axis_angle_to_rotation_matrix`` of ``(0, ry, 0)`` bit for bit
    (:func:`_axis_angle_to_rotation_matrix`, signed zeros included). Without gradients they come from
    :func:`_yaw_rotation_values`, its arithmetic with the zero axes' terms folded (a third of the operations: the photo
    path builds 20 rotations per edit); an ``ry`` that requires grad goes through kornia's operations themselves, so
    its gradients stay theirs too.

    Args:
        ry: ``(...)`` yaw angles in radians.

    Returns:
        ``(..., 3, 3)`` rotation matrices.
    """
    shape = ry.shape
    flat = ry.reshape(-1)
    if flat.requires_grad and torch.is_grad_enabled():
        zeros = torch.zeros_like(flat)
        axis_angle = torch.stack([zeros, flat, zeros], -1)
        return _axis_angle_to_rotation_matrix(axis_angle).reshape(*shape, 3, 3)
    return _yaw_rotation_values(flat).reshape(*shape, 3, 3)


def _yaw_rotation_values(ry: Tensor) -> Tensor:
    """``(N, 3, 3)``: :func:`_axis_angle_to_rotation_matrix` of the axis-angles ``(0, ry, 0)`` for ``ry (N,)``, the
    same bits (NaN payloads aside), without autograd's needs.

    Why each entry is the same: with ``wx = 0 / theta`` and ``wz = 0 / theta`` (+0: ``theta`` is positive, or 1 in
    the series' rows) and ``rx = rz = +0``, kornia's sum ``theta2 = (0 + ry * ry) + 0`` is ``ry * ry``; the
    Rodrigues entries ``c + wx * wx * (1 - c)`` and ``c + wz * wz * (1 - c)`` add +0 (``1 - c >= 0``) to ``c`` (never
    -0), so are ``c``; ``wy * s + wx * wz * (1 - c)`` adds +0 (or a NaN where ``c`` is one, and then ``wy * s`` is
    NaN too); the four zero entries are ``p - q`` (``wxwy * (1 - c) - wz * s`` and ``-wx * s + wywz * (1 - c)``) and
    ``q + p`` with ``p = (wy * 0) * (1 - c)``, ``q = s * 0``, the same signed zeros (``x - y`` is ``x + (-y)``, and
    IEEE products and sums commute). In the series' rows (``theta2 <= 1e-6``) ``ry2 + rz2`` and ``rx2 + ry2`` are
    ``ry2``, ``rx2 + rz2`` is +0, and the off-axis entries keep their products of +0 written out. The series' rows
    are computed only where there are any."""
    theta2 = ry * ry
    mask = theta2 > 1e-6
    theta = torch.sqrt(torch.where(mask, theta2, torch.ones_like(theta2)))  # the series' rows never see sqrt(0)
    wy = ry / theta
    c, s = torch.cos(theta), torch.sin(theta)
    one_minus_c = 1.0 - c
    p = (wy * 0.0) * one_minus_c
    q = s * 0.0
    off_a, off_b = p - q, q + p
    normal = torch.stack([c, off_a, wy * s + 0.0,
                          off_b, c + wy * wy * one_minus_c, off_a,
                          (-wy) * s + 0.0, off_b, c], -1)
    if not bool(mask.all()):
        a = 1.0 - theta2 / 6.0
        b = 0.5 - theta2 / 24.0
        b_zero, a_zero, b_z = b * 0.0, a * 0.0, b * (ry * 0.0)
        diagonal = 1.0 - b * theta2
        off_a, off_b = (-a) * 0.0 + b_z, a_zero + b_z
        taylor = torch.stack([diagonal, off_a, a * ry + b_zero,
                              off_b, 1.0 - b_zero, off_a,
                              (-a) * ry + b_zero, off_b, diagonal], -1)
        normal = torch.where(mask[:, None], normal, taylor)
    return normal.view(-1, 3, 3)


def _axis_angle_to_rotation_matrix(axis_angle: Tensor) -> Tensor:
    """kornia's ``axis_angle_to_rotation_matrix`` (0.9), op for op, so values and gradients are bit-identical,
    without importing kornia at start-up (any kornia module loads all of kornia: about 0.4 s of every command's
    start): Rodrigues' formula, and its Taylor series where ``theta^2 <= 1e-6``. ``(N, 3)`` -> ``(N, 3, 3)``."""
    theta2 = (axis_angle * axis_angle).sum(dim=-1)
    mask = theta2 > 1e-6
    safe_theta2 = torch.where(mask, theta2, torch.ones_like(theta2))  # the Taylor rows never see sqrt(0)

    theta = torch.sqrt(safe_theta2)
    wx, wy, wz = (axis_angle / theta.unsqueeze(-1)).unbind(dim=-1)
    cos_theta, sin_theta = torch.cos(theta), torch.sin(theta)
    one_minus_cos = 1.0 - cos_theta
    wxwy, wxwz, wywz = wx * wy, wx * wz, wy * wz
    rows = (
        (cos_theta + wx * wx * one_minus_cos, wxwy * one_minus_cos - wz * sin_theta,
         wy * sin_theta + wxwz * one_minus_cos),
        (wz * sin_theta + wxwy * one_minus_cos, cos_theta + wy * wy * one_minus_cos,
         -wx * sin_theta + wywz * one_minus_cos),
        (-wy * sin_theta + wxwz * one_minus_cos, wx * sin_theta + wywz * one_minus_cos,
         cos_theta + wz * wz * one_minus_cos),
    )
    normal = torch.stack([torch.stack(row, dim=-1) for row in rows], dim=-2)

    rx, ry, rz = axis_angle.unbind(-1)
    k_one = torch.ones_like(rx)
    a = k_one - theta2 / 6.0
    b = 0.5 * k_one - theta2 / 24.0
    rx2, ry2, rz2 = rx * rx, ry * ry, rz * rz
    rxry, rxrz, ryrz = rx * ry, rx * rz, ry * rz
    taylor = torch.stack(
        [k_one - b * (ry2 + rz2), -a * rz + b * rxry, a * ry + b * rxrz,
         a * rz + b * rxry, k_one - b * (rx2 + rz2), -a * rx + b * ryrz,
         -a * ry + b * rxrz, a * rx + b * ryrz, k_one - b * (rx2 + ry2)],
        dim=-1,
    ).reshape(list(axis_angle.shape[:-1]) + [3, 3])
    return torch.where(mask[..., None, None], normal, taylor)


def wrap_angle(angle: Tensor) -> Tensor:
    """Wrap angles to ``[-pi, pi)``."""
    return torch.remainder(angle + math.pi, 2 * math.pi) - math.pi


def observation_angle(ry: Tensor, x: Tensor, z: Tensor) -> Tensor:
    """KITTI observation angle ``alpha = wrap(ry - atan2(x, z))`` of an object at ``(x, z)``."""
    return wrap_angle(ry - torch.atan2(x, z))


def alpha_bins(alpha: Tensor, num_bins: int = NUM_POSE_BINS) -> Tensor:
    """Index of the pose bin of each observation angle: ``num_bins`` equal bins over [-pi, pi)."""
    width = 2 * math.pi / num_bins
    idx = torch.floor((wrap_angle(alpha) + math.pi) / width).long()
    return idx.clamp_(0, num_bins - 1)
