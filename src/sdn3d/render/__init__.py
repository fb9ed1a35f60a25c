"""Pure-PyTorch renderer: hard z-buffer rasterizer, SoftRas-style soft silhouettes, scene maps.

Batched and device-agnostic (tensors follow the inputs' device). Meshes are padded
``verts (N, V, 3)`` in the KITTI camera frame with ``faces (N, F, 3)`` (padding faces are
``(0, 0, 0)``); intrinsics are ``K`` matrices with pixel centres at integer ``(u, v) = (j, i)``.
"""

from sdn3d.render.maps import (
    SceneMaps,
    depth_map,
    instance_map,
    normal_map,
    pose_map,
    render_scene_maps,
)
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings, SoftSilhouetteSettings, sigma_from_ndc
from sdn3d.render.silhouette import SILHOUETTES, silhouette, straight_through_silhouette
from sdn3d.render.soft import soft_silhouette, soft_silhouette_dense

__all__ = [
    "RasterSettings",
    "SoftSilhouetteSettings",
    "sigma_from_ndc",
    "Fragments",
    "rasterize_meshes",
    "soft_silhouette",
    "soft_silhouette_dense",
    "SILHOUETTES",
    "silhouette",
    "straight_through_silhouette",
    "SceneMaps",
    "instance_map",
    "depth_map",
    "normal_map",
    "pose_map",
    "render_scene_maps",
]
