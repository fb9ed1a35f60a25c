"""Render one frame of a synthetic world: RGB, class map, instance map, depth and object statistics.

The whole scene (static scenery + cars, held-out family shapes or bank templates, with their FFD) is one triangle
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
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.meshes.vehicle_family import VEHICLE_SHAPE_CATEGORY, VEHICLE_SHAPE_NAMES
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings

__all__ = ["RenderedFrame", "FrameGeometry", "render_frame", "render_geometry", "light_frame", "car_meshes",
           "template_bank", "vehicle_bank", "NEAR_CLIP"]

#: Triangles are clipped at this camera-frame z (the rasterizer's near plane is below it).
NEAR_CLIP = 0.15
_RASTER_NEAR = 0.1
_FAR = 1000.0
#: Class id (Car or Van) of each vehicle shape, by shape id.
_SHAPE_CLASS = [CLASS_ID[VEHICLE_SHAPE_CATEGORY[name]] for name in VEHICLE_SHAPE_NAMES]


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


def _wheel_faces(bank: MeshBank) -> Tensor:
    """``(M, Fmax)`` bool mask of wheel faces: the disjoint components of a mesh besides the largest (the body).

    Computed once per cached bank (a loop over its meshes, not over rendered objects).
    """
    wheel = torch.zeros(bank.faces.shape[:2], dtype=torch.bool)
    for m in range(len(bank)):
        nf = int(bank.num_faces[m])
        mesh = trimesh.Trimesh(
            bank.verts[m, : int(bank.num_verts[m])].numpy(), bank.faces[m, :nf].numpy(), process=False
        )
        labels = trimesh.graph.connected_component_labels(mesh.face_adjacency, node_count=nf)
        body = np.bincount(labels).argmax()
        wheel[m, :nf] = torch.from_numpy(labels != body)
    return wheel


@functools.lru_cache(maxsize=1)
def template_bank() -> tuple[MeshBank, Tensor]:
    """The 8-template :class:`MeshBank` and its ``(M, Fmax)`` bool mask of wheel faces (``vehicles='bank'``)."""
    bank = MeshBank.templates()
    return bank, _wheel_faces(bank)


@functools.lru_cache(maxsize=1)
def vehicle_bank() -> tuple[MeshBank, Tensor]:
    """Every vehicle shape (:meth:`MeshBank.vehicle_shapes`, mesh id = shape id) and its wheel-face mask
    (``vehicles='heldout'``)."""
    bank = MeshBank.vehicle_shapes()
    return bank, _wheel_faces(bank)


def car_meshes(world: World, objects: FrameObjects) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """Camera-frame car geometry of a frame, flattened.

    Worlds of 8-template cars (``vehicles='bank'``) gather from :func:`template_bank`, as before the held-out
    family existed (same padding, so the same bits); others from :func:`vehicle_bank`.

    Returns:
        ``verts (N * Vmax, 3)`` float32, ``faces (Fc, 3)`` (real faces only, indices into verts),
        ``face_object (Fc,)`` object index, ``face_wheel (Fc,)`` bool.
    """
    n = len(objects)
    if n == 0:
        empty = torch.zeros(0, dtype=torch.long)
        return torch.zeros(0, 3), torch.zeros(0, 3, dtype=torch.long), empty, empty.bool()
    track = torch.from_numpy(objects.track)
    shape = torch.from_numpy(world.cars.shape)[track]
    bank, wheel = template_bank() if int(shape.max()) < len(TEMPLATE_NAMES) else vehicle_bank()
    verts, faces = bank.gather(shape)
    phi = torch.from_numpy(world.cars.phi)[track]
    deformed = ffd_deform(verts, phi, bank.ffd_basis[shape])
    dims = torch.from_numpy(world.cars.dims).float()[track]
    cam = object_to_camera(
        deformed, dims, torch.from_numpy(objects.ry).float(), torch.from_numpy(objects.center).float()
    )
    vmax = verts.shape[1]
    mask = bank.face_mask[shape]  # (N, Fmax)
    offset = (torch.arange(n) * vmax).view(n, 1, 1)
    flat_faces = (faces + offset)[mask]
    face_object = torch.arange(n).view(n, 1).expand_as(mask)[mask]
    return cam.reshape(-1, 3), flat_faces, face_object, wheel[shape][mask]


def _face_table(world: World, objects: FrameObjects, face_object: Tensor, face_wheel: Tensor) -> Tensor:
    """``(Fs + Fc, 16)`` float attributes of the static faces then the car faces: class, material,
    colour (3), parameters (8), wheel flag, vehicle shape id (-1 static), object index (-1 static)."""
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
    shape = torch.from_numpy(world.cars.shape)[torch.from_numpy(objects.track)][face_object]
    c_tab = torch.cat(
        [
            torch.tensor(_SHAPE_CLASS, dtype=torch.float32)[shape].unsqueeze(1),
            torch.full((face_object.numel(), 1), float(Material.CAR)),
            torch.from_numpy(world.cars.color_rgb).float()[torch.from_numpy(objects.track)][face_object],
            torch.zeros(face_object.numel(), 8),
            face_wheel.float().unsqueeze(1),
            shape.float().unsqueeze(1),
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


@dataclass
class FrameGeometry:
    """What every look of one frame shares: the rasterized scene, its surfaces and object statistics.

    The variations ``clone``, ``morning``, ``sunset``, ``overcast``, ``fog`` and ``rain`` see the same
    objects from the same camera (only the rotated ones move it), so the generator renders the geometry once
    per frame (:func:`render_geometry`) and lights it once per variation (:func:`light_frame`); that gives the
    same bytes as :func:`render_frame` for each of them.

    Attributes:
        world, objects, intrinsics: what was rendered.
        rot, trans: ``(3, 3)``, ``(3,)`` world -> camera rotation and translation.
        depth: ``(H, W)`` float32 z (``inf`` where empty); fg: ``(H, W)`` bool, some surface.
        surface: per foreground pixel (``P`` of them) attributes; albedo ``(P, 3)``, emissive ``(P, 3)``,
            gloss ``(P,)`` from :func:`~sdn3d.data.synth.appearance.surface_albedo` (not to be changed in place).
        p_cam: ``(P, 3)`` camera-frame points; obj: ``(P,)`` object index (-1 none); dims: ``(N, 3)``.
        class_map, instance: ``(H, W)`` int64; stats: per-object statistics.
        tilt: ``(3, 3)`` level -> camera rotation of a pitched camera (``objects`` are in the level frame), else
            None.
    """

    world: World
    objects: FrameObjects
    intrinsics: Intrinsics
    rot: Tensor
    trans: Tensor
    depth: Tensor
    fg: Tensor
    surface: Surface
    albedo: Tensor
    emissive: Tensor
    gloss: Tensor
    p_cam: Tensor
    obj: Tensor
    dims: Tensor
    class_map: Tensor
    instance: Tensor
    stats: ObjectStats
    tilt: Tensor | None = None


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
    return light_frame(render_geometry(world, objects, world_to_cam, intrinsics), variation, frame_seed)


def render_geometry(world: World, objects: FrameObjects, world_to_cam: np.ndarray, intrinsics: Intrinsics
                    ) -> FrameGeometry:
    """The look-independent part of :func:`render_frame`: rasterization, surfaces, albedo, statistics."""
    h, w = intrinsics.size
    rot = torch.from_numpy(world_to_cam[:3, :3]).float()
    trans = torch.from_numpy(world_to_cam[:3, 3]).float()
    static = world.static
    s_verts = torch.from_numpy(static.verts) @ rot.T + trans
    c_verts, c_faces, c_obj, c_wheel = car_meshes(world, objects)
    tilt = world.camera.tilt()  # a pitched camera: the cars are in its level frame (layout module doc)
    tilt = None if tilt is None else torch.from_numpy(tilt).float()
    if tilt is not None:
        c_verts = c_verts @ tilt.T
    n_static_v = s_verts.shape[0]
    verts = torch.cat([s_verts, c_verts])
    faces = torch.cat([torch.from_numpy(static.faces), c_faces + n_static_v])
    verts, faces, parent = clip_near(verts, faces, NEAR_CLIP)

    # Every mesh is closed and outward-wound (boxes, icospheres, templates) and the ground is
    # seen from above, so back faces can be culled: about half the rasterizer's work.
    settings = RasterSettings(image_size=(h, w), near=_RASTER_NEAR, far=_FAR, cull_backfaces=True)
    frags = rasterize_meshes(verts.unsqueeze(0), faces.unsqueeze(0), intrinsics.matrix(), settings)
    pix_face = frags.pix_to_face[0]
    depth = frags.depth[0]
    fg = pix_face >= 0
    # One attribute row per (clipped) face, gathered once per pixel: class, material, colour,
    # material parameters, wheel flag, car template, object index, camera-frame normal.
    table = torch.cat([_face_table(world, objects, c_obj, c_wheel)[parent], _face_normals(verts, faces)], 1)
    attr = table[pix_face[fg]]
    obj = attr[:, 15].long()
    surface, p_cam, dims = _surface(world, objects, attr, fg, depth, rot, trans, intrinsics, tilt)
    road = world.road
    markings = (
        torch.tensor(road.marking_x, dtype=torch.float32),
        torch.tensor(road.marking_dashed),
        road.marking_width,
    )
    albedo, emissive, gloss = surface_albedo(surface, world.seed * 7919 + int(world.name), markings)

    class_map = torch.full((h, w), CLASS_ID["Sky"], dtype=torch.long)
    class_map[fg] = attr[:, 0].long()
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
    return FrameGeometry(world, objects, intrinsics, rot, trans, depth, fg, surface, albedo, emissive, gloss,
                         p_cam, obj, dims, class_map, instance, stats, tilt)


def _surface(world: World, objects: FrameObjects, attr: Tensor, fg: Tensor, depth: Tensor, rot: Tensor,
             trans: Tensor, intrinsics: Intrinsics, tilt: Tensor | None = None) -> tuple[Surface, Tensor, Tensor]:
    """The :class:`Surface` of the ``P`` foreground pixels from their face attributes ``attr (P, 19)``, their
    camera-frame points ``(P, 3)`` and the objects' dims ``(N, 3)`` (``(1, 3)`` ones when there is none)."""
    material = attr[:, 1].long()
    wheel, template, obj = attr[:, 13] > 0.5, attr[:, 14].long(), attr[:, 15].long()
    is_car = obj >= 0
    track = torch.from_numpy(objects.track)
    rows, cols = fg.nonzero(as_tuple=True)
    z = depth[fg]
    fx, fy, cx, cy = intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy
    p_cam = torch.stack([(cols - cx) / fx * z, (rows - cy) / fy * z, z], 1)
    p_world = (p_cam - trans) @ rot
    view_cam = -torch.nn.functional.normalize(p_cam, dim=1)
    dims = torch.from_numpy(world.cars.dims).float()[track] if len(objects) else torch.ones(1, 3)
    local = torch.zeros_like(p_cam)
    if bool(is_car.any()):
        k = obj[is_car]
        centers = torch.from_numpy(objects.center).float()[k]
        r = roty(torch.from_numpy(objects.ry).float())[k]
        p_obj = p_cam[is_car] if tilt is None else p_cam[is_car] @ tilt  # the cars' (level) frame
        local[is_car] = torch.einsum("pk,pkj->pj", p_obj - centers, r) / dims[k]
    surface = Surface(material, attr[:, 2:5], attr[:, 5:13], p_world, attr[:, 16:19] @ rot, view_cam @ rot,
                      z / intrinsics.fx, local, template, wheel)
    return surface, p_cam, dims


def light_frame(geometry: FrameGeometry, variation: str, frame_seed: int) -> RenderedFrame:
    """Light ``geometry`` with a variation's look (sun, shadows, sky, weather, exposure): the rest of
    :func:`render_frame`. ``frame_seed``: seed of per-frame effects (rain streaks)."""
    g = geometry
    look = look_for(variation)
    h, w = g.intrinsics.size
    material, z = g.surface.material, g.depth[g.fg]
    ground = (material == Material.ROAD) | (material == Material.SIDEWALK) | (material == Material.TERRAIN)
    sun_cam = g.rot @ torch.tensor(look.sun_dir)
    shadow = torch.ones_like(z)
    albedo = g.albedo
    # Shadows of the visible cars on ground pixels closer than 80 m (further they are sub-pixel).
    ground = ground & (z < 80.0)
    seen = torch.unique(g.obj[g.obj >= 0])
    if bool(ground.any()) and seen.numel():
        points, sun = (g.p_cam[ground], sun_cam) if g.tilt is None else (g.p_cam[ground] @ g.tilt, g.tilt.T @ sun_cam)
        direct, occlusion = _ground_shadow(points, g.objects.subset(seen.numpy()), g.dims[seen], sun)
        shadow[ground] = direct
        albedo = albedo.clone()  # the geometry's albedo serves every look
        albedo[ground] = albedo[ground] * occlusion.unsqueeze(1)
    radiance = shade(g.surface, albedo, g.emissive, g.gloss, look, shadow)

    image = torch.zeros(h, w, 3)
    image[g.fg] = radiance
    sky_rows, sky_cols = (~g.fg).nonzero(as_tuple=True)
    if sky_rows.numel():
        fx, fy, cx, cy = g.intrinsics.fx, g.intrinsics.fy, g.intrinsics.cx, g.intrinsics.cy
        rays = torch.stack([(sky_cols - cx) / fx, (sky_rows - cy) / fy, torch.ones(sky_rows.shape[0])], 1)
        dirs = torch.nn.functional.normalize(rays, dim=1) @ g.rot
        image[~g.fg] = sky_color(dirs, look, g.world.seed + int(g.world.name))
    image = apply_weather(image, g.depth, look, frame_seed)
    rgb = tonemap(image, look.exposure)
    return RenderedFrame(rgb.numpy(), g.class_map.numpy(), g.instance.numpy(), g.depth.numpy().astype(np.float32),
                         g.stats)
