"""Draw a :class:`~sdn3d.scene.code.SceneCode` into the textural generator's inputs.

Composition (:func:`scene_maps`; the scene's tensors live on the CPU, rendering runs on the
mesh bank's device and the maps come back there):

1. Every object with geometry in front of the camera is posed (FFD, scale, yaw, translation:
   :func:`sdn3d.render.objects.pose_meshes`) and rasterized *alone* with the hard rasterizer, giving
   per-object coverage and depth. All objects go through one batched call, each into its own crop
   window around the only pixels it can contribute (its mask's box, else its projected mesh's box),
   and steps 2-3 run over the covered (object, pixel) pairs only (:func:`_layers`; it equals the
   dense composition over full-frame renders, :func:`sdn3d.reference.scene_maps.dense_layers`, kept as the
   reference).
2. An object covers its 2D ``mask`` if it has one (an observed object keeps its exact visible
   footprint; objects without geometry only have that), else its rendered silhouette.
3. Occlusion follows depth: at each pixel the covering object with the smallest depth wins
   (the z-buffer across objects). The depth of a covered pixel is the object's rendered depth
   there, else (mask pixel outside the silhouette) its box-centre z; objects without geometry
   have no depth and lie behind every object that has one.
4. Every other pixel keeps the scene's semantic map (edits have already relabelled the pixels
   that moved or deleted objects left: :func:`sdn3d.editing.apply.apply_edits`, rule :func:`fill_background`).

The maps follow the formats of :class:`sdn3d.data.datasets.TexturalDataset` (for an unedited
scene from ground truth, :func:`sdn3d.data.scene_gt.scene_from_frame`, the instance, label, ``L``, boundary and
pose maps are identical to the dataset's, and the normals agree wherever the dataset has them: it
keeps a normal only where the object's own render is frontmost among all renders, we keep it
wherever the visible object was rendered): instance map, label map (instances win), instance
label map ``L``, boundaries of ``L``, normals of the visible rendered surface (0 elsewhere),
pose one-hot of the winning object's observation-angle bin over its whole visible region (objects
with geometry only), depth of the visible rendered surface (0 elsewhere) and the code map
(each pixel takes the code of its ``L`` value: the object's, or its class' background code).

"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import torch
from torch import Tensor

from sdn3d.image_ops import boundary_map, flat_nonzero, instance_label_map
from sdn3d.math3d.camera import project_points
from sdn3d.math3d.rotations import NUM_POSE_BINS, alpha_bins, observation_angle
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.render.maps import normal_map
from sdn3d.render.objects import pose_meshes
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import ObjectTable, SceneCode
from sdn3d.scene.fill import scene_code_map

__all__ = [
    "ComposedMaps",
    "posed_meshes",
    "scene_maps",
    "compose_instances",
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


def _renderable(objects: ObjectTable) -> Tensor:
    """``(N,)`` objects drawn from geometry: a template and a centre in front of the camera."""
    return objects.has_geometry & (objects.location[:, 2] > 0)


def _check_templates(objects: ObjectTable, rows: Tensor, bank: MeshBank) -> None:
    if len(rows) and int(objects.template_id[rows].max()) >= len(bank):
        raise ValueError(f"template ids up to {int(objects.template_id[rows].max())} but the bank has {len(bank)} "
                         "meshes")


def _pose(objects: ObjectTable, rows: Tensor, bank: MeshBank) -> tuple[Tensor, Tensor]:
    """Camera-frame ``verts (G, V, 3)`` float32 and ``faces (G, F, 3)`` of ``objects[rows]`` on ``bank``'s device."""
    device = bank.device
    pick = objects.select(rows.cpu())
    return pose_meshes(bank, pick.template_id.to(device), pick.dims.float().to(device), pick.ry.float().to(device),
                       pick.center.float().to(device), pick.phi.to(device))


def posed_meshes(objects: ObjectTable, bank: MeshBank) -> tuple[Tensor, Tensor, Tensor]:
    """Camera-frame meshes of the renderable objects.

    Returns:
        ``rows (G,)`` their indices in ``objects``, ``verts (G, V, 3)`` float32 and ``faces (G, F, 3)``.
    """
    rows = _renderable(objects).nonzero().flatten()
    _check_templates(objects, rows, bank)
    verts, faces = _pose(objects, rows, bank)
    return rows.to(bank.device), verts, faces


@dataclass
class _Layers:
    """Result of steps 1-3 of the module doc.

    ``winner (H, W)`` row of the frontmost covering object (0 where nothing covers), ``visible (H, W)``,
    ``fragments`` ``(1, H, W)`` of the winner where it was rendered there (packed face indices into
    ``verts (G, V, 3)`` / ``faces (G, F, 3)``, the rasterized meshes).
    """

    winner: Tensor
    visible: Tensor
    fragments: Fragments
    verts: Tensor
    faces: Tensor


def _settings(scene: SceneCode, settings: RasterSettings | None) -> RasterSettings:
    size = scene.intrinsics.size
    settings = settings or RasterSettings(image_size=size)
    if settings.image_size != size:
        raise ValueError(f"settings.image_size {settings.image_size} differs from the scene's {size}")
    return settings


def _fallback_depth(objects: ObjectTable, device: torch.device) -> Tensor:
    """``(N,)`` float32 depth where an object covers a pixel it was not rendered at (module doc, step 3)."""
    behind = torch.finfo(torch.float32).max
    return torch.where(objects.has_geometry, objects.center[:, 2], behind).float().to(device)


def _mask_boxes(k: Tensor, i: Tensor, j: Tensor, n: int) -> Tensor:
    """``(n, 4)`` int64 boxes ``(x0, y0, x1, y1)`` (half-open) of the mask pixels ``(i, j)`` of objects ``k``."""
    box = torch.zeros(n, 4, dtype=torch.long, device=k.device)
    big = torch.iinfo(torch.long).max
    box[:, :2] = big
    for col, value, reduce in ((0, j, "amin"), (1, i, "amin"), (2, j + 1, "amax"), (3, i + 1, "amax")):
        box[:, col].scatter_reduce_(0, k, value, reduce)
    return torch.where(box[:, :1] == big, 0, box)


def _projected_boxes(verts: Tensor, K: Tensor, near: float, height: int, width: int) -> Tensor:
    """``(G, 4)`` int64 pixel boxes ``(x0, y0, x1, y1)`` (half-open) holding every pixel a mesh can cover.

    Faces with a vertex at ``z < near`` are culled by the rasterizer, so only vertices at ``z >= near``
    count; one pixel of margin absorbs rounding. Empty (``y1 <= y0``) when no vertex can be drawn.
    """
    v = verts.detach().double()
    ok = torch.isfinite(v).all(-1) & (v[..., 2] >= near)
    safe = torch.where(ok[..., None], v, v.new_tensor([0.0, 0.0, 1.0]))
    uv = project_points(safe, K.double())  # (G, V, 2)
    inf = torch.tensor(float("inf"), dtype=v.dtype, device=v.device)
    lo = torch.where(ok[..., None], uv, inf).amin(1).nan_to_num(posinf=1e9, neginf=-1e9)  # (G, 2)
    hi = torch.where(ok[..., None], uv, -inf).amax(1).nan_to_num(posinf=1e9, neginf=-1e9)
    lo = (lo.floor() - 1).clamp(min=0)
    hi = (hi.ceil() + 2).clamp(min=0).minimum(torch.tensor([width, height], dtype=v.dtype, device=v.device))
    x0, y0 = lo.long().unbind(1)
    x1, y1 = hi.long().unbind(1)
    return torch.stack([x0, y0, x1.clamp(min=x0), y1.clamp(min=y0)], 1)


def _layers(scene: SceneCode, bank: MeshBank, settings: RasterSettings | None) -> _Layers:
    """Steps 1-3 of the module doc, sparse.

    Each drawn object is rasterized alone (one batched call, an image per object) into a crop window
    around the only pixels it can contribute: its mask's bounding box if it has a mask (its cover), else
    its mesh's projected box. The windows share the largest box's size and sit inside the frame. The
    z-buffer across objects then runs over (object, pixel) candidates: mask pixels and rendered pixels
    of mask-less objects, with a minimum depth per pixel and, among its ties, the lowest object row
    (the dense per-object composition's first minimum: :func:`sdn3d.reference.scene_maps.dense_layers`).
    """
    obj = scene.objects
    device = bank.device
    settings = _settings(scene, settings)
    height, width = settings.image_size
    n, hw = len(obj), height * width
    has_mask = obj.has_mask.to(device)
    masks = obj.mask.to(device)
    mask_hw, mask_w = masks.shape[-2] * masks.shape[-1], masks.shape[-1]
    mask_px = flat_nonzero(masks)  # the (object, row, column) of every mask pixel, in nonzero's row-major order
    k, i, j = mask_px // mask_hw, mask_px % mask_hw // mask_w, mask_px % mask_w
    keep = has_mask[k]
    k, i, j = k[keep], i[keep], j[keep]
    # A mask is the object's whole cover: an empty one needs no rendering.
    draw = _renderable(obj).to(device) & (~has_mask | (torch.bincount(k, minlength=n) > 0))
    rows = draw.nonzero().flatten()
    _check_templates(obj, rows.cpu(), bank)
    verts, faces = _pose(obj, rows, bank)
    K = scene.intrinsics.matrix(device=device).double()
    box = torch.where(has_mask[rows, None], _mask_boxes(k, i, j, n)[rows],
                      _projected_boxes(verts, K, settings.near, height, width))
    keep = (box[:, 2] > box[:, 0]) & (box[:, 3] > box[:, 1])
    rows, verts, faces, box = rows[keep], verts[keep], faces[keep], box[keep]
    g = len(rows)
    crop_w = int((box[:, 2] - box[:, 0]).max()) if g else 1
    crop_h = int((box[:, 3] - box[:, 1]).max()) if g else 1
    x0, y0 = box[:, 0].clamp(max=width - crop_w), box[:, 1].clamp(max=height - crop_h)
    # Integer shifts of (cx, cy) are exact in float64, so crop pixel (i, j) is frame pixel (y0 + i, x0 + j).
    K_crop = K.expand(g, 3, 3).clone()
    K_crop[:, 0, 2] -= x0
    K_crop[:, 1, 2] -= y0
    frags = rasterize_meshes(verts, faces, K_crop, dataclasses.replace(settings, image_size=(crop_h, crop_w)),
                             mesh_to_image=torch.arange(g, device=device), batch_size=g)
    crop = crop_h * crop_w
    slot = torch.full((n,), -1, dtype=torch.long, device=device)
    slot[rows] = torch.arange(g, device=device)

    # Candidates of mask-less objects: their rendered pixels.
    free = (~has_mask[rows]).nonzero().flatten()
    c, ci, cj = (frags.mask[free].nonzero() if len(free) else torch.zeros(0, 3, dtype=torch.long, device=device)).T
    c = free[c]
    obj_a, pix_a, flat_a = rows[c], (ci + y0[c]) * width + cj + x0[c], c * crop + ci * crop_w + cj
    # Candidates of masked objects: their mask pixels, rendered there or not.
    c = slot[k]
    drawn = c >= 0
    cc = c.clamp(min=0)
    flat_b = torch.where(drawn, cc * crop + (i - y0[cc]) * crop_w + j - x0[cc], 0) if g else torch.zeros_like(k)
    hit_b = frags.mask.view(-1)[flat_b] & drawn if g else torch.zeros_like(drawn)
    obj_ = torch.cat([obj_a, k])
    pix = torch.cat([pix_a, i * width + j])
    flat = torch.cat([flat_a, flat_b])
    hit = torch.cat([torch.ones_like(obj_a, dtype=torch.bool), hit_b])
    depth = torch.where(hit, frags.depth.view(-1)[flat].float() if g else 0.0, _fallback_depth(obj, device)[obj_])

    # z-buffer across objects: least depth, then the lowest row among equals.
    least = torch.full((hw,), float("inf"), device=device).scatter_reduce_(0, pix, depth, "amin")
    tie = depth == least[pix]
    win = torch.full((hw,), n, dtype=torch.long, device=device).scatter_reduce_(0, pix[tie], obj_[tie], "amin")
    visible = win < n
    chosen = (obj_ == win[pix]) & hit
    p, f = pix[chosen], flat[chosen]
    out = Fragments.empty(1, (height, width), torch.float32, device)
    if g:
        out.pix_to_face.view(-1)[p] = frags.pix_to_face.view(-1)[f]
        out.pix_to_mesh.view(-1)[p] = frags.pix_to_mesh.view(-1)[f]
        out.depth.view(-1)[p] = frags.depth.view(-1)[f].float()
        out.bary.view(-1, 3)[p] = frags.bary.view(-1, 3)[f].float()
    return _Layers(torch.where(visible, win, 0).view(height, width), visible.view(height, width), out, verts, faces)


def compose_instances(scene: SceneCode, bank: MeshBank | None = None, settings: RasterSettings | None = None
                      ) -> Tensor:
    """``(H, W)`` int64 instance map of the scene's objects alone (0 = none), occlusion by depth."""
    bank = bank or default_bank()
    layers = _layers(scene, bank, settings)
    ids = scene.objects.instance_id.to(bank.device)
    return torch.where(layers.visible, ids[layers.winner] if len(ids) else torch.zeros_like(layers.winner), 0)


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
    return _maps(scene, _layers(scene, bank, settings), bank.device, num_bins)


def _maps(scene: SceneCode, layers: _Layers, device: torch.device, num_bins: int) -> ComposedMaps:
    """Steps 4 and the map formats of the module doc from the composition ``layers``."""
    obj = scene.objects
    winner, visible = layers.winner, layers.visible
    ids = obj.instance_id.to(device)
    instance = torch.where(visible, ids[winner] if len(ids) else torch.zeros_like(winner), 0)
    frags = layers.fragments
    depth = torch.where(frags.mask, frags.depth, 0.0)[0].float()
    if len(layers.verts):
        normal = normal_map(frags, layers.verts, layers.faces)[0].float()
    else:
        normal = torch.zeros(3, *winner.shape, device=device)

    geo = obj.has_geometry.to(device)
    alpha = observation_angle(obj.ry, obj.location[:, 0], obj.location[:, 2]).to(device)
    bins = torch.where(geo, alpha_bins(alpha, num_bins), -1)
    pose = torch.zeros(num_bins, winner.numel(), device=device)
    if len(obj):
        pixel_bin = torch.where(visible, bins[winner], -1).view(-1)
        at = (pixel_bin >= 0).nonzero().flatten()
        pose[pixel_bin[at], at] = 1.0
    pose = pose.view(num_bins, *winner.shape)

    label, lmap = instance_label_map(scene.semantic.to(device), instance)
    return ComposedMaps(
        instance=instance,
        label=label,
        instance_label_map=lmap,
        boundary=boundary_map(lmap[None])[0],
        normal=normal,
        pose=pose,
        depth=depth[None],
        feature=scene_code_map(lmap, ids, obj.code.to(device), scene.background_codes.to(device)),
    )
