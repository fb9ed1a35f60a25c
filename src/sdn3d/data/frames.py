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

import torch
from torch import Tensor

from sdn3d.data.records import FrameRecord, load_depth, load_instances, load_rgb, load_semantic
from sdn3d.image_ops import check_size, resize_image, resize_map, to_image_tensor
from sdn3d.math3d.camera import Intrinsics

__all__ = [
    "Frame",
    "resize_frame",
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


def resize_frame(frame: Frame, size: tuple[int, int]) -> Frame:
    """Resize every map of ``frame`` to ``size = (W, H)``; intrinsics follow (anisotropically)."""
    width, height = check_size(size)

    def opt(t: Tensor | None) -> Tensor | None:
        return None if t is None else resize_map(t, (width, height))

    return Frame(
        image=resize_image(frame.image, (width, height)),
        intrinsics=frame.intrinsics.resized(width, height),
        semantic=opt(frame.semantic),
        instances=opt(frame.instances),
        depth=opt(frame.depth),
    )


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
