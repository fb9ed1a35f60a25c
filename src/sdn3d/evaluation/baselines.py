"""The paper's 2D and 2D+ editing baselines (3D-SDN, Sec. 4.1), as edits of the label maps.

A benchmark ``modify`` (``from``, ``to``, ``zoom``, ``ry``) is realised without 3D:

- ``'2d'``: the object's visible 2D region is translated and scaled about ``from``: output pixel
  ``q`` takes the object's pixel ``p = from + (q - to) / s`` (nearest), ``s = (zoom, zoom)``
  (``zoom`` divides the distance, so the image size grows by ``zoom``); rotation is ignored.
- ``'2d+'``: as ``'2d'`` but the width is also squeezed by ``|cos(ry)|``, ``s = (zoom |cos ry|, zoom)``.

``delete`` removes the object. Both baselines share everything else with the 3D edit so that only
the realisation of the edit differs: objects are picked as :func:`sdn3d.editing.apply.ops_from_benchmark`
does, edited and deleted objects are first deleted with :func:`sdn3d.editing.apply.apply_edits` (same
freed pixels), the rest is composed by :func:`sdn3d.scene.maps.scene_maps`, and the warped
regions are pasted back. Without 3D there is no amodal completion (``apply_edits(amodal=False)``): every
freed pixel takes a background label, also where a car behind the edited one was hidden. Occlusion uses
the 2D ground-plane cue: a region whose lowest pixel is lower in the image is nearer (ties go to the edited
object). Codes are kept. With ``geometry='move'`` the normal, pose and depth maps move with the region
(depth divided by ``zoom``); with ``'empty'`` they are zero everywhere (a baseline without any 3D input).

In the photo appearance (:func:`baseline_photo`, what :mod:`sdn3d.editing.photo` is to 3D-SDN) the baselines
paste each edited object's own pixels, moved and scaled the same way (bilinear), over the vacated pixels filled by
the same fill method (:func:`~sdn3d.editing.photo.vacated_hole`, :func:`~sdn3d.editing.photo.fill_hole`, the
``photo.fill`` setting) with the 2D parts of 3D-SDN's removal, made by the same code
(:func:`~sdn3d.editing.photo.fill.removal_guides`): the pieces of the removed objects that their masks' hole missed
(``leftover_pieces``, a side mirror; filled by Telea after the hole), and, for ``fill='rays'``, the rays from the
road's vanishing point voted for by the picture's edges around the removed objects' masks
(``removal_vanishing_point``). Where no edge votes, the baselines, which have no fitted yaw, fall back on the camera's
forward vanishing point (``K``'s principal point: where a level camera's road runs, as 3D-SDN's own last fallback),
not on the picture's centre. What 3D-SDN's removal (:func:`~sdn3d.editing.photo.transfer.render_photo`) has beyond
this is 3D: the removed car's fitted silhouette and its shadow (found around the fitted footprint) join its hole,
thin things in front of the car (found inside the fitted outline) are kept, and the fitted yaw is the vanishing
point's fallback. So on deletes and occluder removals, where no object is pasted, 3D-SDN against these baselines
measures those 3D parts of the removal (session 22 base2d's records).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.data.edit_benchmark import VKITTI_FRAME_SIZE, BenchmarkEntry, BenchmarkOperation, scale_operation
from sdn3d.editing.apply import Delete, EditError, apply_edits
from sdn3d.editing.photo.fill import fill_hole, removal_guides, vacated_hole
from sdn3d.editing.photo.road import PictureLab
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.pick import pick_objects
from sdn3d.image_ops import boundary_map, instance_label_map
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.scene.code import SceneCode
from sdn3d.scene.fill import scene_code_map
from sdn3d.scene.maps import ComposedMaps, compose_instances, scene_maps

__all__ = ["BASELINE_MODES", "baseline_maps", "baseline_photo", "baseline_photos", "warp_regions"]

BASELINE_MODES = ("2d", "2d+")


def warp_regions(regions: Tensor, values: Tensor, src: Tensor, dst: Tensor, scale: Tensor) -> tuple[Tensor, Tensor]:
    """Move ``M`` regions by ``q = dst + scale * (p - src)`` with nearest-pixel inverse sampling.

    Args:
        regions: ``(M, H, W)`` bool source regions.
        values: ``(C, H, W)`` per-pixel maps carried along (normals, pose, depth, ...).
        src, dst: ``(M, 2)`` ``(u, v)`` anchor and its image; ``scale``: ``(M, 2)`` positive ``(s_u, s_v)``.

    Returns:
        ``(M, H, W)`` bool warped regions and ``(M, C, H, W)`` the values sampled with them.
    """
    num, height, width = regions.shape
    v, u = torch.meshgrid(torch.arange(height, dtype=torch.float64), torch.arange(width, dtype=torch.float64),
                          indexing="ij")
    q = torch.stack([u, v], -1).to(regions.device)  # (H, W, 2)
    p = src[:, None, None] + (q[None] - dst[:, None, None]) / scale[:, None, None]  # (M, H, W, 2)
    # Round half up (not half to even) so that a scale of 2 maps every pixel to exactly 2x2 pixels.
    j, i = torch.floor(p[..., 0] + 0.5).long(), torch.floor(p[..., 1] + 0.5).long()
    inside = (j >= 0) & (j < width) & (i >= 0) & (i < height)
    flat = (i.clamp(0, height - 1) * width + j.clamp(0, width - 1)).reshape(num, -1)  # (M, H*W)
    hit = regions.reshape(num, -1).gather(1, flat).reshape(num, height, width) & inside
    channels = values.shape[0]
    sampled = values.reshape(channels, -1)[:, flat].permute(1, 0, 2).reshape(num, channels, height, width)
    return hit, sampled * hit[:, None]


def baseline_maps(scene: SceneCode, entry: BenchmarkEntry | Sequence[BenchmarkOperation], mode: str = "2d",
                  frame_size: tuple[int, int] | None = VKITTI_FRAME_SIZE, geometry: str = "move",
                  bank: MeshBank | None = None, max_distance: float | None = None) -> ComposedMaps:
    """Generator inputs of the ``mode`` baseline's edit of ``scene`` (module doc).

    Args:
        scene: the source scene (its composed maps give the objects' visible regions).
        entry: benchmark operations (coordinates in ``frame_size`` pixels, mapped to the scene's size).
        mode: ``'2d'`` or ``'2d+'``.
        frame_size: ``(W, H)`` of the operations' coordinates; None = the scene's pixels.
        geometry: ``'move'`` or ``'empty'`` (normal / pose / depth maps).
        bank, max_distance: as :func:`sdn3d.editing.apply.apply_edits` / :func:`sdn3d.editing.pick.pick_objects`.
    """
    if mode not in BASELINE_MODES:
        raise ValueError(f"mode must be one of {BASELINE_MODES}, got {mode!r}")
    if geometry not in ("move", "empty"):
        raise ValueError(f"geometry must be 'move' or 'empty', got {geometry!r}")
    bank = bank or default_bank()
    ops = list(entry.operations if isinstance(entry, BenchmarkEntry) else entry)
    if frame_size is not None and tuple(frame_size) != scene.image_size:
        ops = [scale_operation(op, tuple(frame_size), scene.image_size) for op in ops]
    source = scene_maps(scene, bank)
    ids = pick_objects(scene, [op.from_uv for op in ops], None, max_distance, instance_map=source.instance, bank=bank)
    base_scene = apply_edits(scene, [Delete(i) for i in ids], bank, amodal=False)
    base = scene_maps(base_scene, bank)
    device = base.instance.device
    height, width = scene.intrinsics.size

    mods = [(op, i) for op, i in zip(ops, ids, strict=True) if op.kind == "modify"]
    instance = base.instance
    normal, pose, depth = base.normal, base.pose, base.depth
    if mods:
        src, dst, scale = _modify_warps([op for op, _ in mods], mode, device)
        mod_ids = torch.tensor([i for _, i in mods], device=device)
        regions = source.instance[None] == mod_ids[:, None, None]
        carried = torch.cat([source.normal, source.pose, source.depth])
        warped, values = warp_regions(regions, carried, src, dst, scale)
        zoom = scale[:, 1].float()
        values[:, -1] /= zoom[:, None, None]
        # 2D depth cue: lowest pixel row of each region (edited regions first so that they win ties).
        rows = torch.arange(height, device=device)[None, :, None]
        mod_key = torch.where(warped, rows, -1).flatten(1).amax(1)
        base_ids = base.instance.unique()
        base_ids = base_ids[base_ids != 0]
        base_key = torch.where(base.instance[None] == base_ids[:, None, None], rows, -1).flatten(1).amax(1)
        lut_pos = torch.searchsorted(base_ids, base.instance.contiguous()).clamp(max=max(len(base_ids) - 1, 0))
        base_pixel_key = base_key[lut_pos] if len(base_ids) else torch.full_like(base.instance, -1)
        base_pixel_key = torch.where(base.instance != 0, base_pixel_key, -2)
        keys = torch.cat([torch.where(warped, mod_key[:, None, None], -2), base_pixel_key[None]])
        top = keys.argmax(0)
        from_mod = (top < len(mods)) & (keys.amax(0) > -2)
        pick = top.clamp(max=len(mods) - 1)
        instance = torch.where(from_mod, mod_ids[pick], base.instance)
        picked = values.gather(0, pick[None, None].expand(1, values.shape[1], height, width))[0]
        merged = torch.where(from_mod[None], picked, torch.cat([base.normal, base.pose, base.depth]))
        normal, pose, depth = merged[:3], merged[3:-1], merged[-1:]
    if geometry == "empty":
        normal, pose, depth = torch.zeros_like(normal), torch.zeros_like(pose), torch.zeros_like(depth)
    label, lmap = instance_label_map(base_scene.semantic.to(device), instance)
    obj = scene.objects
    return ComposedMaps(instance=instance, label=label, instance_label_map=lmap, boundary=boundary_map(lmap[None])[0],
                        normal=normal, pose=pose, depth=depth,
                        feature=scene_code_map(lmap, obj.instance_id.to(device), obj.code.to(device),
                                         scene.background_codes.to(device)))


def _modify_warps(ops: list, mode: str, device: torch.device) -> tuple[Tensor, Tensor, Tensor]:
    """``(src (M, 2), dst (M, 2), scale (M, 2))`` float64 of the ``modify`` operations (module doc)."""
    src = torch.tensor([op.from_uv for op in ops], dtype=torch.float64, device=device)
    dst = torch.tensor([op.to_uv if op.to_uv is not None else op.from_uv for op in ops], dtype=torch.float64,
                       device=device)
    squeeze = [abs(math.cos(op.ry)) if mode == "2d+" else 1.0 for op in ops]
    scale = torch.tensor([[op.zoom * s, op.zoom] for op, s in zip(ops, squeeze, strict=True)], dtype=torch.float64,
                         device=device)
    if not bool((scale > 0).all()):
        raise EditError(f"{mode}: an edit squeezes an object to zero width (|cos ry| = 0)")
    return src, dst, scale


def baseline_photo(image: Tensor, scene: SceneCode, entry: BenchmarkEntry | Sequence[BenchmarkOperation],
                   mode: str = "2d", frame_size: tuple[int, int] | None = VKITTI_FRAME_SIZE,
                   settings: PhotoSettings | None = None, bank: MeshBank | None = None,
                   max_distance: float | None = None, fill: Tensor | None = None) -> Tensor:
    """The ``mode`` baseline's edit of ``image (3, H, W)`` (float in [0, 1], the scene's size) in the photo
    appearance (module doc): ``(3, H, W)``.

    Every edited object is removed and its pixels filled as 3D-SDN's photo appearance fills them; each ``modify``
    then pastes the object's source pixels at ``q = to + scale * (p - from)`` (bilinear), nearer-looking regions
    (lower bottom row) in front, kept objects included. ``fill (3, H, W)``: the generator's picture of this edit,
    for ``settings.fill='generator'``.
    """
    return baseline_photos(image, scene, entry, (mode,), frame_size, settings, bank, max_distance, {mode: fill})[mode]


def baseline_photos(image: Tensor, scene: SceneCode, entry: BenchmarkEntry | Sequence[BenchmarkOperation],
                    modes: Sequence[str] = BASELINE_MODES, frame_size: tuple[int, int] | None = VKITTI_FRAME_SIZE,
                    settings: PhotoSettings | None = None, bank: MeshBank | None = None,
                    max_distance: float | None = None, fills: dict[str, Tensor | None] | None = None
                    ) -> dict[str, Tensor]:
    """``{mode: baseline_photo(...)}`` for each of ``modes`` (``fills``: each mode's generator picture), the same
    pictures; the removal and its fill, which the modes share (they differ in the pastes), is made once unless
    ``settings.fill='generator'`` fills each with its own picture."""
    bad = [m for m in modes if m not in BASELINE_MODES]
    if bad:
        raise ValueError(f"mode must be one of {BASELINE_MODES}, got {bad[0]!r}")
    settings = settings or PhotoSettings()
    bank = bank or default_bank()
    fills = fills or {}
    ops = list(entry.operations if isinstance(entry, BenchmarkEntry) else entry)
    if frame_size is not None and tuple(frame_size) != scene.image_size:
        ops = [scale_operation(op, tuple(frame_size), scene.image_size) for op in ops]
    instances = compose_instances(scene, bank).cpu()
    ids = pick_objects(scene, [op.from_uv for op in ops], None, max_distance, instance_map=instances, bank=bank)
    image = image.float().cpu()
    gone = torch.tensor(ids, dtype=torch.long)
    keep = (instances != 0) & ~torch.isin(instances, gone)
    hole = vacated_hole(instances, gone, keep, settings)
    # 3D-SDN's removal without its 3D parts (module doc): the leftover pieces and the edges' vanishing point, with no
    # fitted yaw to fall back on (the camera's forward vanishing point).
    lab = PictureLab(image)
    guides = removal_guides(image, scene.intrinsics.matrix(torch.float64), lab, hole, instances, gone, keep, settings)

    def removal(fill: Tensor | None) -> Tensor:
        filled = fill_hole(image, hole, settings, instances != 0, fill, vanishing=guides.vanishing, lab=lab)
        return guides.fill_leftovers(filled, settings)

    shared = None if settings.fill == "generator" else removal(None)
    return {mode: _pasted(shared.clone() if shared is not None else removal(fills.get(mode)),
                          image, instances, keep, ops, ids, mode) for mode in modes}


def _pasted(out: Tensor, image: Tensor, instances: Tensor, keep: Tensor, ops: Sequence[BenchmarkOperation],
            ids: Sequence[int], mode: str) -> Tensor:
    """``out (3, H, W)`` (the picture with the edited objects removed) with each ``modify`` of ``ops`` (``ids``: the
    objects they picked) pasted from ``image`` as the ``mode`` baseline moves it (:func:`baseline_photo`)."""
    mods = [(op, i) for op, i in zip(ops, ids, strict=True) if op.kind == "modify"]
    if not mods:
        return out
    height, width = instances.shape
    src, dst, scale = _modify_warps([op for op, _ in mods], mode, torch.device("cpu"))
    mod_ids = torch.tensor([i for _, i in mods])
    hit, _ = warp_regions(instances[None] == mod_ids[:, None, None], torch.zeros(1, height, width), src, dst, scale)
    v, u = torch.meshgrid(torch.arange(height, dtype=torch.float64), torch.arange(width, dtype=torch.float64),
                          indexing="ij")
    p = src[:, None, None] + (torch.stack([u, v], -1)[None] - dst[:, None, None]) / scale[:, None, None]  # (M, H, W, 2)
    grid = torch.stack([(p[..., 0] + 0.5) / width * 2 - 1, (p[..., 1] + 0.5) / height * 2 - 1], -1).float()
    colours = F.grid_sample(image[None].expand(len(mods), -1, -1, -1), grid, mode="bilinear", padding_mode="border",
                            align_corners=False)  # (M, 3, H, W)
    # 2D depth cue: the lowest row of each region; a kept object in front (lower) hides the pasted one.
    rows = torch.arange(height)[None, :, None]
    mod_key = torch.where(hit, rows, -1).flatten(1).amax(1)  # (M,)
    kept_ids = instances[keep].unique()
    kept_key = torch.where(instances[None] == kept_ids[:, None, None], rows, -1).flatten(1).amax(1)
    lookup = torch.full((int(instances.max()) + 1,), -1, dtype=torch.long)
    lookup[kept_ids] = kept_key
    front = torch.where(keep, lookup[instances], -1)  # (H, W) key of the kept object at each pixel, -1: none
    order = mod_key.argsort()  # farther (higher bottom row) first, so nearer pastes land on top
    for m in order.tolist():
        paste = hit[m] & (front <= mod_key[m])
        out = torch.where(paste[None], colours[m], out)
    return out
