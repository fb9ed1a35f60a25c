"""Resizing frames to the working size, keeping intrinsics consistent.

Pixel convention (:mod:`sdn3d.math3d.camera`): pixel ``(i, j)`` has its centre at
``(u, v) = (j, i)``; resizing maps ``u' + 0.5 = (u + 0.5) * sx`` (and the same for ``v``), which
is what :meth:`Intrinsics.resized` implements and what ``F.interpolate`` does with
``align_corners=False``. Label-like maps (semantic, instance, depth) use ``'nearest-exact'``,
which picks the source pixel containing the target pixel centre (no invented labels or
depths mixed across object edges); RGB uses ``'area'`` when shrinking both axes (anti-aliased)
and ``'bilinear'`` otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.data.records import FrameRecord, load_depth, load_instances, load_rgb, load_semantic
from sdn3d.math3d.camera import Intrinsics

__all__ = [
    "Frame",
    "to_image_tensor",
    "resize_image",
    "resize_map",
    "resize_frame",
    "scale_boxes",
    "intrinsics_vector",
    "load_frame",
]


@dataclass
class Frame:
    """Arrays of one frame as tensors at one size.

    Attributes:
        image: ``(3, H, W)`` float32 in [0, 1].
        intrinsics: intrinsics of this size.
        semantic: ``(H, W)`` int64 or None.
        instances: ``(H, W)`` int64 or None.
        depth: ``(H, W)`` float32 metres or None.
    """

    image: Tensor
    intrinsics: Intrinsics
    semantic: Tensor | None = None
    instances: Tensor | None = None
    depth: Tensor | None = None


def _check_size(size: tuple[int, int], name: str = "size") -> tuple[int, int]:
    if len(tuple(size)) != 2 or any(int(s) != s or s <= 0 for s in size):
        raise ValueError(f"{name} must be two positive integers (W, H), got {size!r}")
    return int(size[0]), int(size[1])


def to_image_tensor(rgb: np.ndarray) -> Tensor:
    """``(H, W, 3)`` uint8 -> ``(3, H, W)`` float32 in [0, 1]."""
    if rgb.ndim != 3 or rgb.shape[-1] != 3:
        raise ValueError(f"rgb must have shape (H, W, 3), got {rgb.shape}")
    return torch.from_numpy(np.ascontiguousarray(rgb)).permute(2, 0, 1).float().div_(255.0)


def resize_image(image: Tensor, size: tuple[int, int]) -> Tensor:
    """Resize a ``(C, H, W)`` float image to ``size = (W, H)`` (area when shrinking, else bilinear)."""
    width, height = _check_size(size)
    if image.dim() != 3 or not image.is_floating_point():
        raise ValueError(f"image must be a float (C, H, W) tensor, got {image.dtype} {tuple(image.shape)}")
    if tuple(image.shape[-2:]) == (height, width):
        return image
    if height <= image.shape[-2] and width <= image.shape[-1]:
        return F.interpolate(image[None], size=(height, width), mode="area")[0]
    # Bilinear weights are convex, so values stay in the input range.
    return F.interpolate(image[None], size=(height, width), mode="bilinear", align_corners=False)[0]


def resize_map(values: Tensor, size: tuple[int, int]) -> Tensor:
    """Resize a ``(H, W)`` label / instance / depth map to ``size = (W, H)`` with nearest-exact."""
    width, height = _check_size(size)
    if values.dim() != 2:
        raise ValueError(f"values must have shape (H, W), got {tuple(values.shape)}")
    if tuple(values.shape) == (height, width):
        return values
    if values.is_floating_point():
        return F.interpolate(values[None, None], size=(height, width), mode="nearest-exact")[0, 0]
    # Integer ids go through float64, which represents every id below 2**53 exactly.
    out = F.interpolate(values[None, None].double(), size=(height, width), mode="nearest-exact")
    return out[0, 0].to(values.dtype)


def resize_frame(frame: Frame, size: tuple[int, int]) -> Frame:
    """Resize every map of ``frame`` to ``size = (W, H)``; intrinsics follow (anisotropically)."""
    width, height = _check_size(size)

    def opt(t: Tensor | None) -> Tensor | None:
        return None if t is None else resize_map(t, (width, height))

    return Frame(
        image=resize_image(frame.image, (width, height)),
        intrinsics=frame.intrinsics.resized(width, height),
        semantic=opt(frame.semantic),
        instances=opt(frame.instances),
        depth=opt(frame.depth),
    )


def scale_boxes(boxes: Tensor, source: Intrinsics, target_size: tuple[int, int]) -> Tensor:
    """Map ``(..., 4)`` boxes ``(l, t, r, b)`` from ``source``'s size to ``target_size = (W, H)``.

    Box coordinates are treated as points under the pixel-centre convention
    (``u' = (u + 0.5) sx - 0.5``), the same map :meth:`Intrinsics.resized` applies to the
    principal point, so a projected point inside the box stays inside after resizing.
    """
    width, height = _check_size(target_size, "target_size")
    if boxes.shape[-1] != 4:
        raise ValueError(f"boxes must have a last dimension of 4 (l, t, r, b), got {tuple(boxes.shape)}")
    sx, sy = width / source.width, height / source.height
    scale = boxes.new_tensor([sx, sy, sx, sy])
    return (boxes + 0.5) * scale - 0.5


def intrinsics_vector(intrinsics: Intrinsics) -> Tensor:
    """``(4,)`` float32 ``(fx, fy, cx, cy)``."""
    return torch.tensor([intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy], dtype=torch.float32)


def load_frame(
    record: FrameRecord,
    size: tuple[int, int] | None = None,
    semantic: bool = True,
    instances: bool = True,
    depth: bool = False,
) -> Frame:
    """Read the requested modalities of ``record`` and resize them to ``size = (W, H)``.

    ``depth`` is zeros when the frame has no depth on disk (e.g. Cityscapes without
    disparity), so that batches keep one layout; every other requested modality must exist.
    """
    image = to_image_tensor(load_rgb(record))
    frame = Frame(
        image=image,
        intrinsics=record.intrinsics,
        semantic=torch.from_numpy(load_semantic(record)).long() if semantic else None,
        instances=torch.from_numpy(load_instances(record)).long() if instances else None,
    )
    if depth:
        if record.depth_path is None:
            frame.depth = torch.zeros(image.shape[-2:], dtype=torch.float32)
        else:
            frame.depth = torch.from_numpy(load_depth(record)).float()
    return frame if size is None else resize_frame(frame, size)
