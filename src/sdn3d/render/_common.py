"""Shared input checks and face set-up for the renderers (private).

Meshes are padded: ``verts (N, V, 3)`` camera-frame vertices and ``faces (N, F, 3)`` (or a
shared ``(F, 3)``) vertex indices; padding faces are ``(0, 0, 0)`` and are culled as
zero-area faces like any other degenerate face. The packed face index of face ``f`` of
mesh ``n`` is ``n * F + f``.
"""

from __future__ import annotations

import torch
from torch import Tensor

from sdn3d.math3d.camera import project_points

__all__ = [
    "check_verts",
    "check_faces",
    "check_intrinsics",
    "face_vertices",
    "project_vertices",
    "twice_area",
    "faces_the_camera",
]

#: Faces whose projected area (in pixels^2, times two) is below this are degenerate.
AREA_EPS = 1e-10


def check_verts(verts: Tensor) -> Tensor:
    if not isinstance(verts, Tensor) or verts.dim() != 3 or verts.shape[-1] != 3:
        shape = tuple(verts.shape) if isinstance(verts, Tensor) else type(verts).__name__
        raise ValueError(f"verts must be a (N, V, 3) tensor of camera-frame points, got {shape}")
    if not verts.is_floating_point():
        raise ValueError(f"verts must be a floating-point tensor, got dtype {verts.dtype}")
    return verts


def check_faces(faces: Tensor, num_meshes: int, num_verts: int, device: torch.device) -> Tensor:
    """Validate ``faces`` and return ``(N, F, 3)`` int64 on ``device`` (a shared ``(F, 3)`` is expanded)."""
    if not isinstance(faces, Tensor) or faces.dim() not in (2, 3) or faces.shape[-1] != 3:
        shape = tuple(faces.shape) if isinstance(faces, Tensor) else type(faces).__name__
        raise ValueError(f"faces must be a (N, F, 3) or shared (F, 3) index tensor, got {shape}")
    if faces.is_floating_point() or faces.is_complex() or faces.dtype == torch.bool:
        raise ValueError(f"faces must be an integer tensor, got dtype {faces.dtype}")
    if faces.dim() == 3 and faces.shape[0] != num_meshes:
        raise ValueError(f"faces has {faces.shape[0]} meshes but verts has {num_meshes}")
    faces = faces.to(device=device, dtype=torch.long)
    if faces.dim() == 2:
        faces = faces.unsqueeze(0).expand(num_meshes, -1, -1)
    if faces.numel() > 0:
        lo, hi = int(faces.min()), int(faces.max())
        if lo < 0 or hi >= num_verts:
            raise ValueError(f"faces index vertices in [{lo}, {hi}] but meshes have {num_verts} vertices")
    return faces


def check_intrinsics(K: Tensor, count: int, dtype: torch.dtype, device: torch.device, what: str) -> Tensor:
    """``K`` as ``(count, 3, 3)``: a ``(3, 3)`` matrix is shared; ``what`` names the batch axis."""
    if not isinstance(K, Tensor) or K.dim() not in (2, 3) or K.shape[-2:] != (3, 3):
        shape = tuple(K.shape) if isinstance(K, Tensor) else type(K).__name__
        raise ValueError(f"K must be a (3, 3) or ({what}, 3, 3) intrinsics tensor, got {shape}")
    if K.dim() == 3 and K.shape[0] != count:
        raise ValueError(f"K has {K.shape[0]} matrices but there are {count} {what}")
    K = K.to(device=device, dtype=dtype)
    if K.dim() == 2:
        K = K.unsqueeze(0).expand(count, 3, 3)
    return K


def face_vertices(values: Tensor, faces: Tensor) -> Tensor:
    """Gather per-vertex ``values (N, V, C)`` into ``(N, F, 3, C)`` with ``faces (N, F, 3)``."""
    num_meshes, num_verts, channels = values.shape
    offset = torch.arange(num_meshes, device=values.device).view(-1, 1, 1) * num_verts
    # index_select: its backward (index_add) is much faster than advanced indexing's.
    flat = values.reshape(num_meshes * num_verts, channels).index_select(0, (faces + offset).view(-1))
    return flat.view(*faces.shape, channels)


def project_vertices(verts: Tensor, K: Tensor, near: float) -> tuple[Tensor, Tensor]:
    """Project vertices, replacing unusable ones so no NaN or inf reaches the graph.

    Args:
        verts: ``(N, V, 3)`` camera-frame vertices.
        K: ``(N, 3, 3)`` per-mesh intrinsics.
        near: vertices at ``z < near`` (or non-finite) are unusable; their faces are culled.

    Returns:
        ``screen (N, V, 2)`` pixel coordinates and ``ok (N, V)``. Unusable vertices are swapped
        for ``(0, 0, 1)`` before projecting (``torch.where``), so their gradient is exactly zero
        instead of NaN.
    """
    ok = torch.isfinite(verts).all(-1) & (verts[..., 2] >= near)
    safe = torch.where(ok.unsqueeze(-1), verts, verts.new_tensor([0.0, 0.0, 1.0]))
    return project_points(safe, K.unsqueeze(1)), ok


def twice_area(screen: Tensor) -> Tensor:
    """Signed doubled area ``(u1 - u0)(v2 - v0) - (u2 - u0)(v1 - v0)`` of ``(..., 3, 2)`` triangles."""
    d1 = screen[..., 1, :] - screen[..., 0, :]
    d2 = screen[..., 2, :] - screen[..., 0, :]
    return d1[..., 0] * d2[..., 1] - d2[..., 0] * d1[..., 1]


def faces_the_camera(corners: Tensor) -> Tensor:
    """``(...,)`` bool: which camera-frame triangles ``corners (..., 3, 3)`` face the camera: their right-hand-rule
    normal ``(v1 - v0) x (v2 - v0)`` points back towards it (the 3D test, whatever the signs in ``K``; the back-face
    culling of ``RasterSettings`` and ``SoftSilhouetteSettings``)."""
    v0, v1, v2 = corners.unbind(-2)
    return (torch.linalg.cross(v1 - v0, v2 - v0, dim=-1) * v0).sum(-1) < 0
