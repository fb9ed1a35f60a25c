"""Rotations about the camera y axis and the observation angle (KITTI conventions)."""

from __future__ import annotations

import math

import torch
from kornia.geometry.conversions import axis_angle_to_rotation_matrix
from torch import Tensor

__all__ = ["roty", "wrap_angle", "observation_angle", "alpha_bins", "NUM_POSE_BINS"]

#: The pose map quantises the observation angle into this many bins over [-pi, pi).
NUM_POSE_BINS = 24


def roty(ry: Tensor) -> Tensor:
    """Rotation about the camera y axis (KITTI devkit ``roty``).

    ``R = [[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]]``; ``ry = 0`` keeps the canonical
    +x (vehicle front) along the camera +x axis.

    Args:
        ry: ``(...)`` yaw angles in radians.

    Returns:
        ``(..., 3, 3)`` rotation matrices.
    """
    shape = ry.shape
    flat = ry.reshape(-1)
    zeros = torch.zeros_like(flat)
    axis_angle = torch.stack([zeros, flat, zeros], -1)
    return axis_angle_to_rotation_matrix(axis_angle).reshape(*shape, 3, 3)


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
