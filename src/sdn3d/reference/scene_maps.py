"""Dense reference of the scene composition: every object rendered over the whole frame.

:func:`sdn3d.scene.maps.scene_maps` rasterizes each object only inside a crop window and composes
sparse (object, pixel) candidates; this reference does the obvious full-frame thing, so tests pin the
fast path's results to it and ``benchmarks/edit_latency.py`` times the two side by side.
"""

from __future__ import annotations

import torch

from sdn3d.math3d.rotations import NUM_POSE_BINS
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import SceneCode
from sdn3d.scene.maps import (
    ComposedMaps,
    _fallback_depth,
    _Layers,
    _maps,
    _settings,
    posed_meshes,
)

__all__ = ["dense_layers", "scene_maps_dense"]


def dense_layers(scene: SceneCode, bank: MeshBank, settings: RasterSettings | None) -> _Layers:
    """Reference of :func:`sdn3d.scene.maps._layers`: every renderable object rendered over the whole frame,
    composed densely.

    Kept to pin the sparse path's results (tests) and time it (``benchmarks/edit_latency.py``).
    """
    obj = scene.objects
    device = bank.device
    settings = _settings(scene, settings)
    height, width = settings.image_size
    rows, verts, faces = posed_meshes(obj, bank)
    g, n = len(rows), len(obj)
    frags = rasterize_meshes(verts, faces, scene.intrinsics.matrix(device=device), settings,
                             mesh_to_image=torch.arange(g, device=device), batch_size=g)
    mask, has_mask = obj.mask.to(device), obj.has_mask.to(device)
    rendered = torch.zeros(n, height, width, dtype=torch.bool, device=device)
    rendered[rows] = frags.mask
    cover = torch.where(has_mask[:, None, None], mask, rendered)
    depth = _fallback_depth(obj, device)[:, None, None].expand(n, height, width).clone()
    depth[rows] = torch.where(frags.mask, frags.depth.float(), depth[rows])
    depth = torch.where(cover, depth, torch.full_like(depth, float("inf")))
    # min(0) rather than argmin(0): the same first-minimum indices, several times faster on CPU.
    winner = depth.min(0).indices if n else torch.zeros(height, width, dtype=torch.long, device=device)
    visible = cover.any(0) if n else torch.zeros(height, width, dtype=torch.bool, device=device)
    out = Fragments.empty(1, (height, width), torch.float32, device)
    if g:
        slot = torch.full((n,), -1, dtype=torch.long, device=device)
        slot[rows] = torch.arange(g, device=device)
        s = slot[winner]
        gi = s.clamp(min=0)[None]
        hit = visible & (s >= 0) & frags.mask.gather(0, gi)[0]
        out.pix_to_face[0] = torch.where(hit, frags.pix_to_face.gather(0, gi)[0], -1)
        out.pix_to_mesh[0] = torch.where(hit, frags.pix_to_mesh.gather(0, gi)[0], -1)
        out.depth[0] = torch.where(hit, frags.depth.gather(0, gi)[0].float(), float("inf"))
        out.bary[0] = torch.where(hit[..., None], frags.bary.gather(0, gi[..., None].expand(1, height, width, 3))[0],
                                  0.0)
    return _Layers(winner, visible, out, verts, faces)


def scene_maps_dense(scene: SceneCode, bank: MeshBank | None = None, settings: RasterSettings | None = None,
                     num_bins: int = NUM_POSE_BINS) -> ComposedMaps:
    """:func:`sdn3d.scene.maps.scene_maps` through the dense reference :func:`dense_layers`."""
    bank = bank or default_bank()
    return _maps(scene, dense_layers(scene, bank, settings), bank.device, num_bins)
