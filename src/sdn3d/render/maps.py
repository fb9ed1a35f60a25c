"""Scene maps from rasterizer fragments: instance, depth, normal and pose maps.

These are the inputs of the textural branch's generator (docs/ARCHITECTURE.md, data flow): the
hard renderer draws the (edited) scene and each map is filled from the visible face.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.math3d.rotations import NUM_POSE_BINS, alpha_bins
from sdn3d.math3d.sums import sum3
from sdn3d.render._common import check_faces, check_verts, face_vertices
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings

__all__ = ["SceneMaps", "instance_map", "depth_map", "normal_map", "pose_map", "render_scene_maps"]


def _per_mesh(values: Tensor, pix_to_mesh: Tensor, name: str) -> Tensor:
    """Look up ``values (N,)`` at ``pix_to_mesh (B, H, W)``; entries of empty pixels are arbitrary."""
    top = int(pix_to_mesh.max()) if pix_to_mesh.numel() > 0 else -1
    if top >= values.shape[0]:
        raise ValueError(f"{name} has {values.shape[0]} entries but the fragments reference mesh {top}")
    if values.shape[0] == 0:
        return values.new_zeros(pix_to_mesh.shape)
    return values.to(pix_to_mesh.device)[pix_to_mesh.clamp(min=0)]


def instance_map(fragments: Fragments, mesh_ids: Tensor) -> Tensor:
    """``(B, H, W)`` int64 id of the visible mesh (``mesh_ids (N,)``, e.g. ``class * 1000 + k``), 0 where empty."""
    if mesh_ids.dim() != 1 or mesh_ids.is_floating_point():
        raise ValueError(
            f"mesh_ids must be a (N,) integer tensor, got {tuple(mesh_ids.shape)} {mesh_ids.dtype}"
        )
    ids = _per_mesh(mesh_ids.long(), fragments.pix_to_mesh, "mesh_ids")
    return torch.where(fragments.mask, ids, torch.zeros_like(ids))


def depth_map(fragments: Fragments, background: float = 0.0) -> Tensor:
    """``(B, H, W)`` camera-frame z of the visible surface, ``background`` where empty (networks want 0, not inf)."""
    return torch.where(fragments.mask, fragments.depth, fragments.depth.new_full((), background))


def normal_map(fragments: Fragments, verts: Tensor, faces: Tensor) -> Tensor:
    """``(B, 3, H, W)`` camera-frame unit normals of the visible faces, zeros where empty.

    Flat shading: one normal per face, ``(v1 - v0) x (v2 - v0)`` normalised, flipped where
    needed so it points towards the camera at that pixel (``n . P < 0`` for the visible surface
    point ``P``, interpolated from the barycentrics). Winding therefore does not matter, and a
    box face looking at the camera gets ``(0, 0, -1)``.

    Args:
        fragments: output of :func:`~sdn3d.render.rasterize_meshes` for these meshes.
        verts: ``(N, V, 3)`` the camera-frame vertices that were rasterized.
        faces: ``(N, F, 3)`` or shared ``(F, 3)`` faces that were rasterized.

    Example:
        >>> import torch
        >>> from sdn3d.render import RasterSettings, normal_map, rasterize_meshes
        >>> verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -3.0, 5.0], [0.0, 3.0, 5.0]]])
        >>> faces = torch.tensor([[0, 1, 2]])
        >>> K = torch.tensor([[10.0, 0.0, 7.5], [0.0, 10.0, 7.5], [0.0, 0.0, 1.0]])
        >>> normals = normal_map(rasterize_meshes(verts, faces, K, RasterSettings((16, 16))), verts, faces)
        >>> normals.shape
        torch.Size([1, 3, 16, 16])
        >>> normals[0, :, 6, 7].tolist() == [0.0, 0.0, -1.0]  # faces the camera
        True
    """
    verts = check_verts(verts)
    faces = check_faces(faces, verts.shape[0], verts.shape[1], verts.device)
    batch, height, width = fragments.pix_to_face.shape
    out = fragments.depth.new_zeros(batch, height, width, 3)
    hit = fragments.mask
    if faces.numel() == 0 or not bool(hit.any()):
        return out.permute(0, 3, 1, 2)
    fverts = face_vertices(verts.detach().to(out.device), faces).reshape(-1, 3, 3)
    packed = fragments.pix_to_face[hit]
    if int(packed.max()) >= fverts.shape[0]:
        raise ValueError(
            "fragments reference faces beyond the given meshes: pass the rasterized verts / faces"
        )
    tri = fverts[packed].to(out.dtype)  # (P, 3, 3)
    normal = torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1)
    point = sum3(fragments.bary[hit].unsqueeze(-1) * tri, 1)
    flip = sum3(normal * point, -1, keepdim=True) > 0
    normal = torch.where(flip, -normal, normal)
    out[hit] = normal / normal.norm(dim=-1, keepdim=True).clamp_min(torch.finfo(out.dtype).tiny)
    return out.permute(0, 3, 1, 2)


def pose_map(fragments: Fragments, alpha: Tensor, num_bins: int = NUM_POSE_BINS) -> Tensor:
    """``(B, num_bins, H, W)`` one-hot observation-angle bin of the visible object, zeros elsewhere.

    ``alpha (N,)`` is quantised with :func:`sdn3d.math3d.rotations.alpha_bins` (equal bins over
    ``[-pi, pi)``); meshes with a non-finite alpha (e.g. the ground) give zeros.

    Example:
        >>> import torch
        >>> from sdn3d.render import RasterSettings, pose_map, rasterize_meshes
        >>> verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -3.0, 5.0], [0.0, 3.0, 5.0]]])
        >>> faces = torch.tensor([[0, 1, 2]])
        >>> K = torch.tensor([[10.0, 0.0, 7.5], [0.0, 10.0, 7.5], [0.0, 0.0, 1.0]])
        >>> pose = pose_map(rasterize_meshes(verts, faces, K, RasterSettings((16, 16))), torch.tensor([0.0]))
        >>> pose.shape
        torch.Size([1, 24, 16, 16])
        >>> pose[0, :, 6, 7].argmax().item(), int(pose.sum())  # alpha = 0 is bin 12 of 24; 72 pixels
        (12, 72)
    """
    if alpha.dim() != 1 or not alpha.is_floating_point():
        raise ValueError(
            f"alpha must be a (N,) floating-point tensor, got {tuple(alpha.shape)} {alpha.dtype}"
        )
    if num_bins <= 0:
        raise ValueError(f"num_bins must be positive, got {num_bins}")
    finite = torch.isfinite(alpha)
    bins = torch.where(finite, alpha_bins(torch.where(finite, alpha, torch.zeros_like(alpha)), num_bins), -1)
    pixel_bin = _per_mesh(bins, fragments.pix_to_mesh, "alpha")
    pixel_bin = torch.where(fragments.mask, pixel_bin, torch.full_like(pixel_bin, -1))
    levels = torch.arange(num_bins, device=pixel_bin.device).view(1, -1, 1, 1)
    return (pixel_bin.unsqueeze(1) == levels).to(fragments.depth.dtype)


@dataclass
class SceneMaps:
    """Maps of ``B`` rendered scenes.

    Attributes:
        instance: ``(B, H, W)`` int64 instance ids, 0 where empty.
        depth: ``(B, H, W)`` camera-frame z, 0 where empty.
        normal: ``(B, 3, H, W)`` camera-facing unit normals, 0 where empty.
        pose: ``(B, num_bins, H, W)`` one-hot pose bins inside objects with a finite alpha.
        mask: ``(B, H, W)`` bool, true where some mesh is visible.
    """

    instance: Tensor
    depth: Tensor
    normal: Tensor
    pose: Tensor
    mask: Tensor


def render_scene_maps(
    verts: Tensor,
    faces: Tensor,
    K: Tensor,
    settings: RasterSettings,
    mesh_ids: Tensor,
    alpha: Tensor,
    mesh_to_image: Tensor | None = None,
    batch_size: int | None = None,
    num_bins: int = NUM_POSE_BINS,
) -> SceneMaps:
    """Rasterize padded meshes and build all scene maps (see :func:`rasterize_meshes` for inputs).

    Args:
        mesh_ids: ``(N,)`` instance id of each mesh (0 for stuff such as the ground, if wanted).
        alpha: ``(N,)`` observation angle of each mesh, NaN for meshes without a pose.

    Example:
        >>> import torch
        >>> from sdn3d.render import RasterSettings, render_scene_maps
        >>> verts = torch.tensor([[[-3.0, -3.0, 5.0], [3.0, -3.0, 5.0], [0.0, 3.0, 5.0]]])  # one car's mesh
        >>> faces = torch.tensor([[0, 1, 2]])
        >>> K = torch.tensor([[10.0, 0.0, 7.5], [0.0, 10.0, 7.5], [0.0, 0.0, 1.0]])
        >>> maps = render_scene_maps(verts, faces, K, RasterSettings(image_size=(16, 16)),
        ...                          mesh_ids=torch.tensor([12001]), alpha=torch.tensor([0.0]))
        >>> maps.instance.shape, maps.normal.shape, maps.pose.shape
        (torch.Size([1, 16, 16]), torch.Size([1, 3, 16, 16]), torch.Size([1, 24, 16, 16]))
        >>> maps.instance[0, 6, 7].item(), maps.depth[0, 6, 7].item(), maps.depth[0, 0, 0].item()
        (12001, 5.0, 0.0)
    """
    fragments = rasterize_meshes(verts, faces, K, settings, mesh_to_image, batch_size)
    return SceneMaps(
        instance=instance_map(fragments, mesh_ids),
        depth=depth_map(fragments),
        normal=normal_map(fragments, verts, faces),
        pose=pose_map(fragments, alpha, num_bins),
        mask=fragments.mask,
    )
