"""Place template meshes in the camera frame: the bridge from object attributes to renderer input."""

from __future__ import annotations

import torch
from torch import Tensor

from sdn3d.math3d.ffd import ffd_deform
from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import MeshBank

__all__ = ["pose_meshes"]


def pose_meshes(
    bank: MeshBank,
    template_ids: Tensor,
    dims: Tensor,
    ry: Tensor,
    center: Tensor,
    phi: Tensor | None = None,
) -> tuple[Tensor, Tensor]:
    """Deform, scale, rotate and translate template meshes into the camera frame.

    Args:
        bank: the mesh templates (padded, with cached FFD bases).
        template_ids: ``(N,)`` long template index per object.
        dims: ``(N, 3)`` object size ``(l, h, w)`` in metres.
        ry: ``(N,)`` yaw about the camera y axis.
        center: ``(N, 3)`` box centre ``c = (x3d, y3d - h/2, z3d)`` in the camera frame.
        phi: optional ``(N, 64, 3)`` FFD control displacements (``None`` = undeformed).

    Returns:
        ``verts (N, V, 3)`` camera-frame vertices and ``faces (N, F, 3)`` (padding faces
        ``(0, 0, 0)``), ready for :func:`sdn3d.render.rasterize_meshes` or
        :func:`sdn3d.render.soft_silhouette`. Differentiable w.r.t. dims, ry, center and phi.
    """
    if template_ids.dim() != 1:
        raise ValueError(f"pose_meshes: template_ids must be (N,), got {tuple(template_ids.shape)}")
    n = template_ids.shape[0]
    for name, value, shape in (("dims", dims, (n, 3)), ("ry", ry, (n,)), ("center", center, (n, 3))):
        if tuple(value.shape) != shape:
            raise ValueError(f"pose_meshes: {name} must have shape {shape}, got {tuple(value.shape)}")
    verts, faces = bank.gather(template_ids)
    verts = verts.to(dims.dtype)
    if phi is not None:
        if tuple(phi.shape) != (n, 64, 3):
            raise ValueError(f"pose_meshes: phi must have shape {(n, 64, 3)}, got {tuple(phi.shape)}")
        basis = bank.ffd_basis.to(template_ids.device)[template_ids].to(phi.dtype)
        verts = ffd_deform(verts.to(phi.dtype), phi, basis)
    cam = object_to_camera(verts, dims, ry, center)
    # keep padding vertices exactly at the object's centre so padded faces stay degenerate
    valid = torch.arange(verts.shape[1], device=verts.device)[None] < bank.num_verts.to(verts.device)[
        template_ids
    ].unsqueeze(1)
    cam = torch.where(valid.unsqueeze(-1), cam, center.unsqueeze(1).expand_as(cam))
    return cam, faces
