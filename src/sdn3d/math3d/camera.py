"""Pinhole camera in the KITTI convention (x right, y down, z forward, metres).

Pixel convention: pixel ``(row i, column j)`` has its centre at ``(u, v) = (j, i)``;
the image spans ``[-0.5, W - 0.5] x [-0.5, H - 0.5]``. Virtual KITTI's
``cx = 620.5`` for ``W = 1242`` is exactly the image centre under this convention.
Intrinsics keep ``fx``, ``fy``, ``cx``, ``cy`` separately because resizing to a
working size (624x192 from 1242x375) is anisotropic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

__all__ = [
    "as_intrinsics_matrix",
    "CameraPose",
    "DEFAULT_CAMERA_HEIGHT",
    "ROLL_TOLERANCE",
    "Intrinsics",
    "VKITTI_INTRINSICS",
    "project_points",
    "unproject_pixels",
    "intrinsics_matrix",
]


@dataclass(frozen=True)
class Intrinsics:
    """Pinhole intrinsics of one image size.

    Args:
        fx, fy: focal lengths in pixels.
        cx, cy: principal point in pixels (pixel-centre convention, see module doc).
        width, height: image size in pixels.
    """

    fx: float
    fy: float
    cx: float
    cy: float
    width: int
    height: int

    def __post_init__(self) -> None:
        for name in ("fx", "fy", "cx", "cy"):
            value = float(getattr(self, name))
            if not torch.isfinite(torch.tensor(value)):
                raise ValueError(f"Intrinsics.{name} must be finite, got {value}")
        if self.fx <= 0 or self.fy <= 0:
            raise ValueError(f"Intrinsics focal lengths must be positive, got fx={self.fx}, fy={self.fy}")
        if int(self.width) <= 0 or int(self.height) <= 0:
            raise ValueError(f"Intrinsics image size must be positive, got {self.width}x{self.height}")

    @property
    def size(self) -> tuple[int, int]:
        """``(height, width)``, the order tensors use."""
        return (int(self.height), int(self.width))

    def matrix(self, dtype: torch.dtype = torch.float32, device: torch.device | str | None = None) -> Tensor:
        """The ``(3, 3)`` calibration matrix K."""
        return torch.tensor(
            [[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]], dtype=dtype, device=device
        )

    def resized(self, width: int, height: int) -> Intrinsics:
        """Intrinsics of the same camera after resizing the image to ``width x height``.

        Scale factors may differ per axis. With pixel centres at integer coordinates,
        ``u' + 0.5 = (u + 0.5) * sx``, hence ``cx' = (cx + 0.5) * sx - 0.5``.
        """
        sx = width / self.width
        sy = height / self.height
        return Intrinsics(
            fx=self.fx * sx,
            fy=self.fy * sy,
            cx=(self.cx + 0.5) * sx - 0.5,
            cy=(self.cy + 0.5) * sy - 0.5,
            width=int(width),
            height=int(height),
        )

    def cropped(self, left: float, top: float, width: int, height: int) -> Intrinsics:
        """Intrinsics of the crop whose top-left pixel centre is at ``(left, top)``."""
        return Intrinsics(self.fx, self.fy, self.cx - left, self.cy - top, int(width), int(height))

    def to_dict(self) -> dict[str, float | int]:
        return {
            "fx": self.fx,
            "fy": self.fy,
            "cx": self.cx,
            "cy": self.cy,
            "width": self.width,
            "height": self.height,
        }


#: Virtual KITTI 1.3.1 (and 2) camera at its native 1242x375 resolution.
VKITTI_INTRINSICS = Intrinsics(fx=725.0, fy=725.0, cx=620.5, cy=187.0, width=1242, height=375)


#: The road's depth below the camera when the camera does not say (KITTI / Virtual KITTI: 1.65 m).
DEFAULT_CAMERA_HEIGHT = 1.65

#: Largest roll (radians) a level virtual camera ignores (:meth:`CameraPose.level_intrinsics`): 0.01 rad moves a
#: point at the image edge of a 2048-px-wide Cityscapes frame by about 10 px (3 px at the 624-px working size).
ROLL_TOLERANCE = 0.01


@dataclass(frozen=True)
class CameraPose:
    """How the camera sits over the road: the road is a plane ``height`` metres below the camera centre,
    seen by a camera pitched by ``pitch`` and rolled by ``roll`` (radians).

    Conventions are Cityscapes' (``camera.json`` ``extrinsic``, vehicle frame ISO 8855 x forward, y left, z up,
    camera orientation ``Rz(yaw) Ry(pitch) Rx(roll)``, :func:`sdn3d.data.cityscapes.camera_to_vehicle`): a
    positive ``pitch`` looks down (the horizon above the principal point: Cityscapes' cameras have about
    0.04 rad), a positive ``roll`` turns the camera about its optical axis from left to up. Yaw about the vertical
    does not change the road plane and is not kept.

    The *level* camera frame is the camera frame of the same camera with no pitch or roll (KITTI axes: x right,
    y down, z forward); in it the road is the plane ``y = height``, the frame the box fit works in
    (:class:`sdn3d.geometric.fit.FitSettings` ``camera_height``).
    """

    height: float = DEFAULT_CAMERA_HEIGHT
    pitch: float = 0.0
    roll: float = 0.0

    def __post_init__(self) -> None:
        for name in ("height", "pitch", "roll"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"CameraPose.{name} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if self.height <= 0:
            raise ValueError(f"CameraPose.height must be positive (metres above the road), got {self.height}")
        for name in ("pitch", "roll"):
            if abs(getattr(self, name)) >= math.pi / 4:
                raise ValueError(f"CameraPose.{name} must be within +-pi/4 rad (a street camera), got "
                                 f"{getattr(self, name)}")

    @property
    def level(self) -> bool:
        """No pitch and no roll."""
        return self.pitch == 0.0 and self.roll == 0.0

    def tilt(self) -> np.ndarray:
        """``(3, 3)`` float64 rotation from the level camera frame to the camera frame (KITTI axes):
        ``p_cam = tilt @ p_level``. The identity for a level camera."""
        cp, sp, cr, sr = math.cos(self.pitch), math.sin(self.pitch), math.cos(self.roll), math.sin(self.roll)
        ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])  # ISO 8855 axes (x forward, y left, z up)
        rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
        iso_to_kitti = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
        return (iso_to_kitti @ ry @ rx @ iso_to_kitti.T).T  # camera -> level is the inner product

    def level_intrinsics(self, intr: Intrinsics) -> Intrinsics:
        """The level virtual camera of this camera's image: the pitch folded into the principal point,
        ``cy' = cy - fy tan(pitch)`` (exact on the horizon and at the principal point's column; a point
        ``a`` rad below the horizon moves by a factor ``1 / (1 + tan(a) tan(pitch))`` of its distance to it:
        under 1.5 % for a 0.045 rad pitch at the bottom of a Cityscapes frame). The roll is ignored (up to
        :data:`ROLL_TOLERANCE`, :meth:`roll_ignored`)."""
        if self.pitch == 0.0:
            return intr
        return Intrinsics(intr.fx, intr.fy, intr.cx, intr.cy - intr.fy * math.tan(self.pitch), intr.width,
                          intr.height)

    @property
    def roll_ignored(self) -> bool:
        """The roll is over :data:`ROLL_TOLERANCE` and the level virtual camera leaves it out."""
        return abs(self.roll) > ROLL_TOLERANCE

    def to_dict(self) -> dict[str, float]:
        return {"height": self.height, "pitch": self.pitch, "roll": self.roll}


def intrinsics_matrix(fx: Tensor, fy: Tensor, cx: Tensor, cy: Tensor) -> Tensor:
    """Batched calibration matrices from ``(B,)`` tensors; returns ``(B, 3, 3)``."""
    zeros = torch.zeros_like(fx)
    ones = torch.ones_like(fx)
    rows = [
        torch.stack([fx, zeros, cx], -1),
        torch.stack([zeros, fy, cy], -1),
        torch.stack([zeros, zeros, ones], -1),
    ]
    return torch.stack(rows, -2)


def project_points(points: Tensor, K: Tensor) -> Tensor:
    """Project camera-frame points to pixels.

    Args:
        points: ``(..., 3)`` camera-frame points, ``z > 0`` in front of the camera.
        K: ``(3, 3)`` or ``(..., 3, 3)`` broadcastable calibration matrices.

    Returns:
        ``(..., 2)`` pixel coordinates ``(u, v)``.
    """
    # kornia's project_points (0.9), op for op so values and gradients are bit-identical, without importing kornia
    # at start-up (all of kornia loads with any of its modules: about 0.4 s of every command's start).
    K = K.expand(*points.shape[:-1], 3, 3)
    z = points[..., -1:]
    valid = torch.abs(z) > 1e-8  # kornia's divide guard: no divide at |z| <= 1e-8
    scale = torch.where(valid, 1.0 / torch.where(valid, z, torch.ones_like(z)), torch.ones_like(z))
    return scale * points[..., :-1] * K[..., :2, :2].diagonal(dim1=-2, dim2=-1) + K[..., :2, 2]


def unproject_pixels(uv: Tensor, depth: Tensor, K: Tensor) -> Tensor:
    """Inverse of :func:`project_points` for a given camera-frame depth ``z``.

    Args:
        uv: ``(..., 2)`` pixel coordinates.
        depth: ``(..., 1)`` or ``(...)`` camera-frame z.
        K: ``(3, 3)`` or broadcastable ``(..., 3, 3)``.

    Returns:
        ``(..., 3)`` camera-frame points.
    """
    if depth.dim() == uv.dim() - 1:
        depth = depth.unsqueeze(-1)
    K = K.expand(*uv.shape[:-1], 3, 3)
    # kornia's unproject_points (0.9), op for op (see project_points)
    xy = (uv - K[..., :2, 2]) / K[..., :2, :2].diagonal(dim1=-2, dim2=-1)
    return torch.cat([xy, torch.ones_like(xy[..., :1])], dim=-1) * depth


def as_intrinsics_matrix(K: Tensor, batch: int | None = None) -> Tensor:
    """``(N, 4)`` vectors ``(fx, fy, cx, cy)``, ``(N, 3, 3)`` or ``(3, 3)`` -> ``(N, 3, 3)`` matrices.

    ``batch`` expands a single ``(3, 3)`` / ``(4,)`` calibration to ``N`` objects.
    """
    if K.dim() == 1 and K.shape[0] == 4:
        K = K.unsqueeze(0)
    if K.dim() == 2 and K.shape[1] == 4:
        K = intrinsics_matrix(K[:, 0], K[:, 1], K[:, 2], K[:, 3])
    elif K.dim() == 2 and K.shape == (3, 3):
        K = K.unsqueeze(0)
    elif K.dim() != 3 or K.shape[1:] != (3, 3):
        raise ValueError(f"K must have shape (N, 4) as (fx, fy, cx, cy), (N, 3, 3) or (3, 3), got {tuple(K.shape)}")
    if batch is not None:
        if K.shape[0] not in (1, batch):
            raise ValueError(f"K has {K.shape[0]} calibrations but there are {batch} objects")
        K = K.expand(batch, 3, 3)
    return K
