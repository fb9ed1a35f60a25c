"""Object crops for the geometric branch, batched: boxes of masks, square windows, crop intrinsics.

:func:`crop_windows` is the batched form of :func:`sdn3d.data.datasets.geometric.crop_maps` (same
sampling, bit for bit), so :func:`sdn3d.derender.derender` feeds the branch exactly the crops of
:class:`~sdn3d.data.datasets.GeometricDataset`, all objects in one ``grid_sample``.
"""

from __future__ import annotations

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.math3d.camera import Intrinsics

__all__ = ["mask_boxes", "crop_windows", "crop_intrinsics"]


def mask_boxes(masks: Tensor) -> Tensor:
    """``(N, 4)`` float ``(l, t, r, b)`` pixel-centre boxes (inclusive) of ``masks (N, H, W)``; empty: zeros."""
    if masks.dim() != 3:
        raise ValueError(f"masks must be (N, H, W), got {tuple(masks.shape)}")
    n, height, width = masks.shape
    cols, rows = masks.any(1), masks.any(2)
    xs = torch.arange(width, device=masks.device).expand(n, width)
    ys = torch.arange(height, device=masks.device).expand(n, height)
    box = torch.stack([torch.where(cols, xs, width).amin(1), torch.where(rows, ys, height).amin(1),
                       torch.where(cols, xs, -1).amax(1), torch.where(rows, ys, -1).amax(1)], 1)
    return torch.where(masks.flatten(1).any(1, keepdim=True), box, 0).float()


def crop_windows(maps: Tensor, windows: Tensor, size: int, mode: str) -> Tensor:
    """Resample ``N`` square windows of ``maps`` to ``(N, C, size, size)`` in one ``grid_sample``.

    Batched :func:`~sdn3d.data.datasets.geometric.crop_maps`: output pixel ``j`` of window
    ``(left, top, side)`` samples ``u = left + (j + 0.5) side / size - 0.5`` (zeros outside).

    Args:
        maps: ``(C, H, W)`` shared by all windows, or ``(N, C, H, W)`` one per window.
        windows: ``(N, 3)`` ``(left, top, side)`` in pixels.
        mode: ``'bilinear'`` or ``'nearest'``.
    """
    if windows.dim() != 2 or windows.shape[1] != 3:
        raise ValueError(f"windows must be (N, 3) (left, top, side), got {tuple(windows.shape)}")
    n = windows.shape[0]
    if maps.dim() == 3:
        maps = maps[None].expand(n, *maps.shape)
    if maps.dim() != 4 or maps.shape[0] != n:
        raise ValueError(f"maps must be (C, H, W) or (N={n}, C, H, W), got {tuple(maps.shape)}")
    height, width = maps.shape[-2:]
    w = windows.to(device=maps.device, dtype=torch.float32)
    # The same float32 operations as crop_maps, so both give identical samples (nearest picks included).
    centres = (torch.arange(size, dtype=torch.float32, device=maps.device) + 0.5)[None] * (w[:, 2:3] / size) - 0.5
    gx = (w[:, :1] + centres) * (2.0 / width) + (1.0 / width - 1.0)  # (N, S)
    gy = (w[:, 1:2] + centres) * (2.0 / height) + (1.0 / height - 1.0)
    grid = torch.stack([gx[:, None, :].expand(n, size, size), gy[:, :, None].expand(n, size, size)], -1)
    return F.grid_sample(maps.float(), grid, mode=mode, padding_mode="zeros", align_corners=False)


def crop_intrinsics(intr: Intrinsics, windows: Tensor, size: int) -> Tensor:
    """``(N, 4)`` ``(fx, fy, cx, cy)`` of each window resized to ``size`` (``Intrinsics.cropped().resized()``)."""
    w = windows.double()
    scale = size / w[:, 2]
    return torch.stack([intr.fx * scale, intr.fy * scale, (intr.cx - w[:, 0] + 0.5) * scale - 0.5,
                        (intr.cy - w[:, 1] + 0.5) * scale - 0.5], 1).float()
