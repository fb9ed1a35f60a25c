"""Draw a :class:`~sdn3d.scene.SceneCode` into the textural generator's inputs.

Composition (:func:`scene_maps`; the scene's tensors live on the CPU, rendering runs on the
mesh bank's device and the maps come back there):

1. Every object with geometry in front of the camera is posed (FFD, scale, yaw, translation:
   :func:`sdn3d.render.objects.pose_meshes`) and rasterized *alone* into its own image with the
   hard rasterizer, giving per-object coverage and depth ``(N, H, W)``.
2. An object covers its 2D ``mask`` if it has one (an observed object keeps its exact visible
   footprint; objects without geometry only have that), else its rendered silhouette.
3. Occlusion follows depth: at each pixel the covering object with the smallest depth wins
   (the z-buffer across objects). The depth of a covered pixel is the object's rendered depth
   there, else (mask pixel outside the silhouette) its box-centre z; objects without geometry
   have no depth and lie behind every object that has one.
4. Every other pixel keeps the scene's semantic map (edits have already relabelled the pixels
   that moved or deleted objects left: :func:`sdn3d.edit.apply_edits`, rule :func:`fill_background`).

The maps follow the formats of :class:`sdn3d.data.datasets.TexturalDataset` (for an unedited
scene from ground truth, :meth:`SceneCode.from_frame`, the instance, label, ``L``, boundary and
pose maps are identical to the dataset's, and the normals agree wherever the dataset has them: it
keeps a normal only where the object's own render is frontmost among all renders, we keep it
wherever the visible object was rendered): instance map, label map (instances win), instance
label map ``L``, boundaries of ``L``, normals of the visible rendered surface (0 elsewhere),
pose one-hot of the winning object's observation-angle bin over its whole visible region (objects
with geometry only), depth of the visible rendered surface (0 elsewhere) and the code map
(each pixel takes the code of its ``L`` value: the object's, or its class' background code).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import torch
from scipy.ndimage import distance_transform_edt
from torch import Tensor

from sdn3d.data.datasets.textural import boundary_map, instance_label_map
from sdn3d.data.records import IGNORE_INDEX, INSTANCE_DIVISOR
from sdn3d.geometry.rotations import NUM_POSE_BINS, alpha_bins, observation_angle
from sdn3d.meshes.bank import MeshBank
from sdn3d.render.maps import normal_map
from sdn3d.render.objects import pose_meshes
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene import ObjectTable, SceneCode

__all__ = [
    "ComposedMaps",
    "default_bank",
    "posed_meshes",
    "scene_maps",
    "compose_instances",
    "code_map",
    "fill_background",
]


@dataclass
class ComposedMaps:
    """Generator inputs of one scene (keys and formats of :class:`~sdn3d.data.datasets.TexturalDataset`).

    Attributes:
        instance: ``(H, W)`` int64 instance ids, 0 = none.
        label: ``(H, W)`` int64 semantic classes, instance classes win.
        instance_label_map: ``(H, W)`` int64 ``L``: instance id on objects, class elsewhere.
        boundary: ``(1, H, W)`` float32 boundaries of ``L``.
        normal: ``(3, H, W)`` float32 camera-frame normals of the visible rendered surface.
        pose: ``(num_bins, H, W)`` float32 one-hot observation-angle bins.
        depth: ``(1, H, W)`` float32 camera-frame z of the visible rendered surface, 0 elsewhere.
        feature: ``(C, H, W)`` float32 texture code of each pixel's ``L`` value.
    """

    instance: Tensor
    label: Tensor
    instance_label_map: Tensor
    boundary: Tensor
    normal: Tensor
    pose: Tensor
    depth: Tensor
    feature: Tensor

    def as_dict(self) -> dict[str, Tensor]:
        return dict(self.__dict__)


@functools.cache
def default_bank() -> MeshBank:
    """The 8 procedural templates (built once per process)."""
    return MeshBank.templates()


def _renderable(objects: ObjectTable) -> Tensor:
    """``(N,)`` objects drawn from geometry: a template and a centre in front of the camera."""
    return objects.has_geometry & (objects.location[:, 2] > 0)


def posed_meshes(objects: ObjectTable, bank: MeshBank) -> tuple[Tensor, Tensor, Tensor]:
    """Camera-frame meshes of the renderable objects.

    Returns:
        ``rows (G,)`` their indices in ``objects``, ``verts (G, V, 3)`` float32 and ``faces (G, F, 3)``.
    """
    rows = _renderable(objects).nonzero().flatten()
    if len(rows) and int(objects.template_id[rows].max()) >= len(bank):
        raise ValueError(f"template ids up to {int(objects.template_id[rows].max())} but the bank has {len(bank)} "
                         "meshes")
    device = bank.device
    pick = objects.select(rows)
    verts, faces = pose_meshes(bank, pick.template_id.to(device), pick.dims.float().to(device),
                               pick.ry.float().to(device), pick.center.float().to(device), pick.phi.to(device))
    return rows.to(device), verts, faces


def _layers(scene: SceneCode, bank: MeshBank, settings: RasterSettings | None) -> tuple:
    """Per-object rendering and the per-pixel winner (steps 1-3 of the module doc)."""
    obj = scene.objects
    device = bank.device
    height, width = scene.intrinsics.size
    settings = settings or RasterSettings(image_size=(height, width))
    if settings.image_size != (height, width):
        raise ValueError(f"settings.image_size {settings.image_size} differs from the scene's {(height, width)}")
    rows, verts, faces = posed_meshes(obj, bank)
    g = len(rows)
    frags = rasterize_meshes(verts, faces, scene.intrinsics.matrix(device=device), settings,
                             mesh_to_image=torch.arange(g, device=device), batch_size=g)
    n = len(obj)
    mask, has_mask = obj.mask.to(device), obj.has_mask.to(device)
    rendered = torch.zeros(n, height, width, dtype=torch.bool, device=device)
    rendered[rows] = frags.mask
    cover = torch.where(has_mask[:, None, None], mask, rendered)
    # Fallback depth where an object covers a pixel it was not rendered at (see module doc).
    behind = torch.finfo(torch.float32).max
    fallback = torch.where(obj.has_geometry, obj.center[:, 2], behind).float().to(device)
    depth = fallback[:, None, None].expand(n, height, width).clone()
    depth[rows] = torch.where(frags.mask, frags.depth.float(), depth[rows])
    depth = torch.where(cover, depth, torch.full_like(depth, float("inf")))
    # min(0) rather than argmin(0): the same first-minimum indices, several times faster on CPU.
    winner = depth.min(0).indices if n else torch.zeros(height, width, dtype=torch.long, device=device)
    visible = cover.any(0) if n else torch.zeros(height, width, dtype=torch.bool, device=device)
    return rows, verts, faces, frags, winner, visible


def compose_instances(scene: SceneCode, bank: MeshBank | None = None, settings: RasterSettings | None = None
                      ) -> Tensor:
    """``(H, W)`` int64 instance map of the scene's objects alone (0 = none), occlusion by depth."""
    bank = bank or default_bank()
    _, _, _, _, winner, visible = _layers(scene, bank, settings)
    ids = scene.objects.instance_id.to(bank.device)
    return torch.where(visible, ids[winner] if len(ids) else torch.zeros_like(winner), 0)


def scene_maps(scene: SceneCode, bank: MeshBank | None = None, settings: RasterSettings | None = None,
               num_bins: int = NUM_POSE_BINS) -> ComposedMaps:
    """Render and compose ``scene`` (module doc) on ``bank``'s device.

    Args:
        scene: the scene.
        bank: template meshes indexed by the objects' ``template_id`` (default: the 8 templates).
        settings: rasterizer settings of the scene's size (default near 0.1 m, far 1000 m).
        num_bins: pose bins.
    """
    bank = bank or default_bank()
    device = bank.device
    obj = scene.objects
    rows, verts, faces, frags, winner, visible = _layers(scene, bank, settings)
    height, width = scene.intrinsics.size
    ids = obj.instance_id.to(device)
    instance = torch.where(visible, ids[winner] if len(ids) else torch.zeros_like(winner), 0)

    # Fragments of the winning object at each pixel, where it was rendered there.
    slot = torch.full((len(obj),), -1, dtype=torch.long, device=device)
    slot[rows] = torch.arange(len(rows), device=device)
    g = slot[winner] if len(obj) else torch.full_like(winner, -1)
    gi = g.clamp(min=0)[None]
    hit = visible & (g >= 0)
    if len(rows):
        hit &= frags.mask.gather(0, gi)[0]
        pix_to_face = torch.where(hit, frags.pix_to_face.gather(0, gi)[0], -1)
        bary = frags.bary.gather(0, gi[..., None].expand(1, height, width, 3))[0]
        depth = torch.where(hit, frags.depth.gather(0, gi)[0], torch.zeros((), device=device)).float()
        merged = Fragments(pix_to_face[None], torch.where(hit, g, -1)[None], depth[None], bary[None])
        normal = normal_map(merged, verts, faces)[0].float()
    else:
        depth = torch.zeros(height, width, device=device)
        normal = torch.zeros(3, height, width, device=device)

    geo = obj.has_geometry.to(device)
    alpha = observation_angle(obj.ry, obj.location[:, 0], obj.location[:, 2]).to(device)
    bins = torch.where(geo, alpha_bins(alpha, num_bins), -1)
    pixel_bin = torch.where(visible, bins[winner] if len(obj) else -torch.ones_like(winner), -1)
    pose = (pixel_bin[None] == torch.arange(num_bins, device=device)[:, None, None]).float()

    label, lmap = instance_label_map(scene.semantic.to(device), instance)
    return ComposedMaps(
        instance=instance,
        label=label,
        instance_label_map=lmap,
        boundary=boundary_map(lmap),
        normal=normal,
        pose=pose,
        depth=depth[None],
        feature=code_map(lmap, ids, obj.code.to(device), scene.background_codes.to(device)),
    )


def code_map(label_map: Tensor, instance_ids: Tensor, codes: Tensor, background_codes: Tensor) -> Tensor:
    """``(C, H, W)`` code of each pixel's ``L`` value (the generator's z-map).

    Args:
        label_map: ``(H, W)`` ``L`` (instance ids >= 1000, classes below; 255 ignore gets zeros).
        instance_ids: ``(N,)`` object ids with ``codes (N, C)``; ids absent from ``L`` are unused,
            object pixels of unknown ids get zeros.
        background_codes: ``(num_classes, C)``.
    """
    num, dim = background_codes.shape
    is_obj = label_map >= INSTANCE_DIVISOR
    # One gather for the background: row ``num`` of the extended table is the zero code.
    table = torch.cat([background_codes, background_codes.new_zeros(1, dim)])
    known = ~is_obj & (label_map >= 0) & (label_map < num)
    out = table[torch.where(known, label_map, num)]
    if len(instance_ids) and bool(is_obj.any()):
        order = instance_ids.argsort()
        sorted_ids = instance_ids[order]
        values = label_map[is_obj]
        pos = torch.searchsorted(sorted_ids, values).clamp(max=len(sorted_ids) - 1)
        found = sorted_ids[pos] == values
        out[is_obj] = codes[order[pos]].to(out.dtype) * found[:, None]
    return out.permute(2, 0, 1)


def fill_background(semantic: Tensor, vacated: Tensor, thing_classes: Tensor) -> Tensor:
    """Relabel ``vacated`` pixels with background: the label of the nearest *source* pixel.

    Source pixels are those not vacated, not of an instance class (``thing_classes``, so that
    freed regions never grow car-coloured blobs without an instance) and not ignore (255);
    nearest in Euclidean pixel distance (``scipy.ndimage.distance_transform_edt`` indices, ties
    broken by scipy). A car removed from a road thus takes road labels below the horizon and the
    labels of what is beside it above. If no pixel qualifies, the thing/ignore exclusions are
    dropped; if every pixel is vacated, the map is returned unchanged.

    Args:
        semantic: ``(H, W)`` int64 class map.
        vacated: ``(H, W)`` bool.
        thing_classes: ``(T,)`` class ids with instances.
    """
    if semantic.shape != vacated.shape:
        raise ValueError(f"semantic {tuple(semantic.shape)} and vacated {tuple(vacated.shape)} must match")
    if not bool(vacated.any()):
        return semantic.clone()
    sem, vac = semantic.cpu().numpy(), vacated.cpu().numpy().astype(bool)
    source = ~vac & ~np.isin(sem, thing_classes.cpu().numpy()) & (sem != IGNORE_INDEX)
    if not source.any():
        source = ~vac
    if not source.any():
        return semantic.clone()
    _, (ii, jj) = distance_transform_edt(~source, return_indices=True)
    out = sem.copy()
    out[vac] = sem[ii[vac], jj[vac]]
    return torch.from_numpy(out).to(semantic.device)
