"""Render one frame of a synthetic world: RGB, class map, instance map, depth and object statistics.

The whole scene (static scenery + cars from the template bank with their FFD) is one triangle
mesh, clipped at the near plane here (the project's hard rasterizer culls faces crossing it)
and rasterized once, so semantics, instances, depth and occlusion come from the same z-buffer.
Per-object statistics for the motgt file come from a second rasterizer call that draws every
car alone (see :func:`object_statistics`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import torch
import trimesh
from torch import Tensor

from sdn3d.data.synth.appearance import (
    Surface,
    apply_weather,
    look_for,
    shade,
    sky_color,
    surface_albedo,
    tonemap,
)
from sdn3d.data.synth.classes import CLASS_ID, Material
from sdn3d.data.synth.clip import clip_near
from sdn3d.data.synth.layout import FrameObjects, World
from sdn3d.data.synth.primitives import StaticMesh
from sdn3d.data.synth.stats import ObjectStats, object_statistics
from sdn3d.math3d.camera import Intrinsics
from sdn3d.math3d.ffd import ffd_deform
from sdn3d.math3d.rotations import roty
from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import MeshBank
from sdn3d.meshes.templates import TEMPLATE_CATEGORY, TEMPLATE_NAMES
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings

__all__ = ["RenderedFrame", "render_frame", "car_meshes", "template_bank", "NEAR_CLIP"]

#: Triangles are clipped at this camera-frame z (the rasterizer's near plane is below it).
NEAR_CLIP = 0.15
_RASTER_NEAR = 0.1
_FAR = 1000.0
#: Class id (Car or Van) of each template.
_TEMPLATE_CLASS = [CLASS_ID[TEMPLATE_CATEGORY[name]] for name in TEMPLATE_NAMES]


@dataclass
class RenderedFrame:
    """One rendered frame.

    Attributes:
        rgb: ``(H, W, 3)`` uint8.
        class_map: ``(H, W)`` int64 class ids (``classes.CLASS_NAMES``; empty pixels are Sky).
        instance: ``(H, W)`` int64 index into the frame's objects, -1 where no car is visible.
        depth: ``(H, W)`` float32 camera-frame z in metres, ``inf`` where empty (sky).
        stats: per-object statistics (visible pixels, 2D box, truncation, occupancy).
    """

    rgb: np.ndarray
    class_map: np.ndarray
    instance: np.ndarray
    depth: np.ndarray
    stats: ObjectStats


@functools.lru_cache(maxsize=1)
def template_bank() -> tuple[MeshBank, Tensor]:
    """The 8-template :class:`MeshBank` and a ``(M, Fmax)`` bool mask of wheel faces.

    Wheels are the disjoint components of a template besides the largest (the body).
    """
    bank = MeshBank.templates()
    wheel = torch.zeros(bank.faces.shape[:2], dtype=torch.bool)
    for m in range(len(bank)):
        nf = int(bank.num_faces[m])
        mesh = trimesh.Trimesh(
            bank.verts[m, : int(bank.num_verts[m])].numpy(), bank.faces[m, :nf].numpy(), process=False
        )
        labels = trimesh.graph.connected_component_labels(mesh.face_adjacency, node_count=nf)
        body = np.bincount(labels).argmax()
        wheel[m, :nf] = torch.from_numpy(labels != body)
    return bank, wheel


def car_meshes(world: World, objects: FrameObjects) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """Camera-frame car geometry of a frame, flattened.

    Returns:
        ``verts (N * Vmax, 3)`` float32, ``faces (Fc, 3)`` (real faces only, indices into verts),
        ``face_object (Fc,)`` object index, ``face_wheel (Fc,)`` bool.
    """
    bank, wheel = template_bank()
    n = len(objects)
    if n == 0:
        empty = torch.zeros(0, dtype=torch.long)
        return torch.zeros(0, 3), torch.zeros(0, 3, dtype=torch.long), empty, empty.bool()
    track = torch.from_numpy(objects.track)
    template = torch.from_numpy(world.cars.template)[track]
    verts, faces = bank.gather(template)
    phi = torch.from_numpy(world.cars.phi)[track]
    deformed = ffd_deform(verts, phi, bank.ffd_basis[template])
    dims = torch.from_numpy(world.cars.dims).float()[track]
    cam = object_to_camera(
        deformed, dims, torch.from_numpy(objects.ry).float(), torch.from_numpy(objects.center).float()
    )
    vmax = verts.shape[1]
    mask = bank.face_mask[template]  # (N, Fmax)
    offset = (torch.arange(n) * vmax).view(n, 1, 1)
    flat_faces = (faces + offset)[mask]
    face_object = torch.arange(n).view(n, 1).expand_as(mask)[mask]
    return cam.reshape(-1, 3), flat_faces, face_object, wheel[template][mask]


def _face_table(world: World, objects: FrameObjects, face_object: Tensor, face_wheel: Tensor) -> Tensor:
    """``(Fs + Fc, 16)`` float attributes of the static faces then the car faces: class, material,
    colour (3), parameters (8), wheel flag, template (-1 static), object index (-1 static)."""
    static = world.static
    n = static.num_faces
    s_tab = torch.cat(
        [
            torch.from_numpy(static.face_class).float().unsqueeze(1),
            torch.from_numpy(static.face_material).float().unsqueeze(1),
            torch.from_numpy(static.face_color),
            torch.from_numpy(static.face_param),
            torch.zeros(n, 1),
            torch.full((n, 2), -1.0),
        ],
        1,
    )
    if face_object.numel() == 0:
        return s_tab
    template = torch.from_numpy(world.cars.template)[torch.from_numpy(objects.track)][face_object]
    c_tab = torch.cat(
        [
            torch.tensor(_TEMPLATE_CLASS, dtype=torch.float32)[template].unsqueeze(1),
            torch.full((face_object.numel(), 1), float(Material.CAR)),
            torch.from_numpy(world.cars.color_rgb).float()[torch.from_numpy(objects.track)][face_object],
            torch.zeros(face_object.numel(), 8),
            face_wheel.float().unsqueeze(1),
            template.float().unsqueeze(1),
            face_object.float().unsqueeze(1),
        ],
        1,
    )
    return torch.cat([s_tab, c_tab])


def _face_normals(verts: Tensor, faces: Tensor) -> Tensor:
    """Unit camera-frame normals ``(F, 3)`` oriented towards the camera (at the origin)."""
    tri = verts[faces]
    normal = torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1)
    normal = torch.nn.functional.normalize(normal, dim=1, eps=1e-12)
    facing = (normal * tri.mean(1)).sum(1) > 0
    return torch.where(facing.unsqueeze(1), -normal, normal)


def _ground_shadow(points: Tensor, objects: FrameObjects, dims: Tensor, sun_cam: Tensor) -> tuple[Tensor, Tensor]:
    """Soft car shadows on ground points ``(P, 3)`` (camera frame): ``(direct_light, ambient_occlusion)``.

    A car's shadow is its footprint rectangle with soft edges: once under the car (ambient
    occlusion) and once shifted away from the sun (at most 2.5 m) for the direct light.
    """
    if len(objects) == 0 or points.shape[0] == 0:
        ones = torch.ones(points.shape[0])
        return ones, ones
    center = torch.from_numpy(objects.center).float()
    ry = torch.from_numpy(objects.ry).float()
    cos, sin = torch.cos(ry), torch.sin(ry)
    rise = (-sun_cam[1]).clamp(min=0.05)
    shift = -sun_cam[[0, 2]] / rise * (dims[:, 1:2] / 2)  # away from the sun, (N, 2)
    shift = shift * (2.5 / shift.norm(dim=1, keepdim=True).clamp(min=2.5))

    def box(offset: Tensor, margin: float, soft: float) -> Tensor:
        dx = points[:, :1] - (center[:, 0] + offset[:, 0])  # (P, N)
        dz = points[:, 2:] - (center[:, 2] + offset[:, 1])
        lx = (cos * dx - sin * dz).abs()  # R_y(ry)^T (p - c), x and z rows
        lz = (sin * dx + cos * dz).abs()
        ix = ((dims[:, 0] / 2 + margin - lx) / soft + 0.5).clamp(0, 1)
        iz = ((dims[:, 2] / 2 + margin - lz) / soft + 0.5).clamp(0, 1)
        return (ix * iz).amax(1)

    direct = 1.0 - 0.85 * box(shift, 0.05, 0.5)
    occlusion = 1.0 - 0.45 * box(torch.zeros_like(shift), 0.15, 0.6)
    return direct, occlusion


def _occluder_boxes(verts: Tensor, faces: Tensor, parent: Tensor, static: StaticMesh, intr: Intrinsics) -> Tensor:
    """``(M, 5)`` screen boxes ``(umin, vmin, umax, vmax)`` and nearest z of the (clipped) scenery
    faces that can hide a car: all but the flat ground (road, sidewalk, terrain), on which cars stand."""
    n_static = static.num_faces
    is_static = parent < n_static
    material = torch.from_numpy(static.face_material)[parent.clamp(max=n_static - 1)]
    flat = (material == Material.ROAD) | (material == Material.SIDEWALK) | (material == Material.TERRAIN)
    tri = verts[faces[is_static & ~flat]]  # (M, 3, 3), z >= NEAR_CLIP after clipping
    u = tri[..., 0] / tri[..., 2] * intr.fx + intr.cx
    v = tri[..., 1] / tri[..., 2] * intr.fy + intr.cy
    return torch.stack([u.amin(1), v.amin(1), u.amax(1), v.amax(1), tri[..., 2].amin(1)], 1)


def render_frame(
    world: World,
    objects: FrameObjects,
    world_to_cam: np.ndarray,
    intrinsics: Intrinsics,
    variation: str,
    frame_seed: int,
) -> RenderedFrame:
    """Render ``objects`` (camera frame) in ``world`` seen from ``world_to_cam`` with a variation's look.

    Args:
        world: the sampled world (scenery, car tracks).
        objects: the frame's cars, camera frame.
        world_to_cam: ``(4, 4)`` extrinsics.
        intrinsics: image size and calibration.
        variation: selects lighting and weather (``appearance.LOOKS``).
        frame_seed: seed of per-frame effects (rain streaks).
    """
    look = look_for(variation)
    h, w = intrinsics.size
    rot = torch.from_numpy(world_to_cam[:3, :3]).float()
    trans = torch.from_numpy(world_to_cam[:3, 3]).float()
    static = world.static
    s_verts = torch.from_numpy(static.verts) @ rot.T + trans
    c_verts, c_faces, c_obj, c_wheel = car_meshes(world, objects)
    n_static_v = s_verts.shape[0]
    verts = torch.cat([s_verts, c_verts])
    faces = torch.cat([torch.from_numpy(static.faces), c_faces + n_static_v])
    verts, faces, parent = clip_near(verts, faces, NEAR_CLIP)

    # Every mesh is closed and outward-wound (boxes, icospheres, templates) and the ground is
    # seen from above, so back faces can be culled: about half the rasterizer's work.
    settings = RasterSettings(image_size=(h, w), near=_RASTER_NEAR, far=_FAR, cull_backfaces=True)
    K = intrinsics.matrix()
    frags = rasterize_meshes(verts.unsqueeze(0), faces.unsqueeze(0), K, settings)
    pix_face = frags.pix_to_face[0]
    depth = frags.depth[0]
    fg = pix_face >= 0
    face = pix_face[fg]
    # One attribute row per (clipped) face, gathered once per pixel: class, material, colour,
    # material parameters, wheel flag, car template, object index, camera-frame normal.
    table = torch.cat([_face_table(world, objects, c_obj, c_wheel)[parent], _face_normals(verts, faces)], 1)
    attr = table[face]
    cls, material = attr[:, 0].long(), attr[:, 1].long()
    color, param = attr[:, 2:5], attr[:, 5:13]
    wheel, template, obj = attr[:, 13] > 0.5, attr[:, 14].long(), attr[:, 15].long()
    normal_cam = attr[:, 16:19]
    is_car = obj >= 0
    cars = world.cars
    track = torch.from_numpy(objects.track)

    rows, cols = fg.nonzero(as_tuple=True)
    z = depth[fg]
    fx, fy, cx, cy = intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy
    p_cam = torch.stack([(cols - cx) / fx * z, (rows - cy) / fy * z, z], 1)
    p_world = (p_cam - trans) @ rot
    view_cam = -torch.nn.functional.normalize(p_cam, dim=1)
    dims = torch.from_numpy(cars.dims).float()[track] if len(objects) else torch.ones(1, 3)
    local = torch.zeros_like(p_cam)
    if bool(is_car.any()):
        k = obj[is_car]
        centers = torch.from_numpy(objects.center).float()[k]
        r = roty(torch.from_numpy(objects.ry).float())[k]
        local[is_car] = torch.einsum("pk,pkj->pj", p_cam[is_car] - centers, r) / dims[k]
    surface = Surface(
        material,
        color,
        param,
        p_world,
        normal_cam @ rot,
        view_cam @ rot,
        z / intrinsics.fx,
        local,
        template,
        wheel,
    )
    road = world.road
    markings = (
        torch.tensor(road.marking_x, dtype=torch.float32),
        torch.tensor(road.marking_dashed),
        road.marking_width,
    )
    albedo, emissive, gloss = surface_albedo(surface, world.seed * 7919 + int(world.name), markings)

    ground = (material == Material.ROAD) | (material == Material.SIDEWALK) | (material == Material.TERRAIN)
    sun_cam = rot @ torch.tensor(look.sun_dir)
    shadow = torch.ones_like(z)
    # Shadows of the visible cars on ground pixels closer than 80 m (further they are sub-pixel).
    ground = ground & (z < 80.0)
    seen = torch.unique(obj[obj >= 0])
    if bool(ground.any()) and seen.numel():
        direct, occlusion = _ground_shadow(p_cam[ground], objects.subset(seen.numpy()), dims[seen], sun_cam)
        shadow[ground] = direct
        albedo[ground] = albedo[ground] * occlusion.unsqueeze(1)
    radiance = shade(surface, albedo, emissive, gloss, look, shadow)

    image = torch.zeros(h, w, 3)
    image[fg] = radiance
    sky_rows, sky_cols = (~fg).nonzero(as_tuple=True)
    if sky_rows.numel():
        rays = torch.stack([(sky_cols - cx) / fx, (sky_rows - cy) / fy, torch.ones(sky_rows.shape[0])], 1)
        dirs = torch.nn.functional.normalize(rays, dim=1) @ rot
        image[~fg] = sky_color(dirs, look, world.seed + int(world.name))
    image = apply_weather(image, depth, look, frame_seed)
    rgb = tonemap(image, look.exposure)

    class_map = torch.full((h, w), CLASS_ID["Sky"], dtype=torch.long)
    class_map[fg] = cls
    instance = torch.full((h, w), -1, dtype=torch.long)
    instance[fg] = obj
    stats = object_statistics(
        c_verts,
        c_faces,
        c_obj,
        len(objects),
        instance,
        intrinsics,
        NEAR_CLIP,
        _RASTER_NEAR,
        _FAR,
        cull_backfaces=True,
        occluders=_occluder_boxes(verts, faces, parent, static, intrinsics),
    )
    return RenderedFrame(rgb.numpy(), class_map.numpy(), instance.numpy(), depth.numpy().astype(np.float32), stats)
