"""Per-object 2D statistics of a rendered frame, as Virtual KITTI's motgt reports them.

- ``visible``: pixels of the object in the frame's instance map (after occlusion).
- ``box``: ``(l, t, r, b)`` inclusive pixel bounds of the *visible* pixels (what Virtual KITTI's
  2D boxes bound); ``-1`` for invisible objects.
- ``unoccluded``: pixels the object covers inside the frame when drawn alone (rendered on a
  crop of the frame around its projection: same pixel grid, so the count is exact).
- ``visible_fraction = visible / unoccluded``: the share of the object's in-frame pixels that are not
  occluded (independent of truncation). Only the generator knows it; it sets the KITTI-like ``occluded`` flag.
- ``occupr = visible / ((r - l + 1) (b - t + 1))``: the share of the 2D box (the inclusive box of the visible
  pixels, the one the motgt row holds) that the visible pixels cover, as real Virtual KITTI 1.3.1 motgt
  ``occupr`` and Virtual KITTI 2 ``occupancy_ratio`` are defined (unoccluded cars read about 0.75-0.85
  there: a car's silhouette does not fill its box). It is what a reader of real files can know.
- ``truncr``: share of the object's unoccluded silhouette outside the frame. Objects whose
  projected vertices all lie in the image have ``truncr = 0`` exactly; for the others the car is
  drawn alone a second time on a 384x192 canvas with the image plane scaled by ``s`` and shifted
  (intrinsics ``K' = diag(s, s, 1) K`` plus an offset) so that its whole silhouette fits, and
  ``truncr = 1 - inside / total`` is counted there (``inside`` = pixels whose frame coordinates
  lie in the frame): an estimate at that canvas's resolution. Cars crossing the near plane are
  clipped at it; their silhouette extends far outside the frame and ``truncr`` comes out close
  to 1.

Each pass is one batched rasterizer call (one image per drawn car).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

from sdn3d.data.synth.clip import clip_near
from sdn3d.math3d.camera import Intrinsics
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings

__all__ = ["ObjectStats", "object_statistics", "visible_boxes"]

#: Scaled canvases leave this margin so the whole silhouette is strictly inside.
_FIT = 0.94
#: Canvas ``(H, W)`` on which truncated cars are drawn whole (at most at the frame's scale).
_CANVAS = (192, 384)


@dataclass
class ObjectStats:
    """Arrays over a frame's N objects (see the module doc): visible ``(N,)`` int64, box ``(N, 4)``
    int64, unoccluded ``(N,)`` int64, truncr ``(N,)`` float64, occupr ``(N,)`` float64 (visible / box
    area), visible_fraction ``(N,)`` float64 (visible / unoccluded); 0 for invisible objects."""

    visible: np.ndarray
    box: np.ndarray
    unoccluded: np.ndarray
    truncr: np.ndarray
    occupr: np.ndarray
    visible_fraction: np.ndarray


def _pairwise_hits(boxes: Tensor, zmax: Tensor, others: Tensor) -> Tensor:
    """``(N, M)``: screen box ``n`` (``(N, 5)`` umin, vmin, umax, vmax, zmin) meets box ``m`` of
    ``others`` (``(M, 5)``) within one pixel and ``m`` comes nearer than ``zmax[n]``."""
    return (
        (others[:, 0] <= boxes[:, 2:3] + 1.0)
        & (others[:, 2] >= boxes[:, 0:1] - 1.0)
        & (others[:, 1] <= boxes[:, 3:4] + 1.0)
        & (others[:, 3] >= boxes[:, 1:2] - 1.0)
        & (others[:, 4] < zmax.unsqueeze(1))
    )


def _may_be_hidden(boxes: Tensor, zmax: Tensor, occluders: Tensor, chunk: int = 4096) -> Tensor:
    """``(N,)``: some occluder box meets box ``n`` and is nearer (chunks bound the memory)."""
    hit = torch.zeros(boxes.shape[0], dtype=torch.bool)
    for start in range(0, occluders.shape[0], chunk):
        hit |= _pairwise_hits(boxes, zmax, occluders[start : start + chunk]).any(1)
    return hit


def _size_groups(area: Tensor, ratio: float = 4.0) -> list[Tensor]:
    """Split crops into groups of similar area (largest first; a group's smallest crop is at least
    ``1 / ratio`` of its largest): one rasterizer call per group, so one big crop does not make
    every crop of the batch big. Returns index tensors into ``area``."""
    order = torch.argsort(area, descending=True, stable=True)
    sizes = area[order].double()
    group_id = torch.zeros_like(order)
    # Greedy over at most a handful of groups: a new group starts below largest / ratio.
    start, gid = 0, 0
    while start < order.numel():
        limit = sizes[start] / ratio
        stop = start + int((sizes[start:] >= limit).sum())
        group_id[start:stop] = gid
        start, gid = stop, gid + 1
    return [order[group_id == g] for g in range(gid)]


def visible_boxes(instance: Tensor, count: int) -> tuple[Tensor, Tensor]:
    """Visible pixel counts ``(N,)`` and inclusive boxes ``(N, 4)`` (l, t, r, b; -1 if unseen).

    Args:
        instance: ``(H, W)`` int64 object index per pixel, -1 for none.
        count: number of objects N.
    """
    rows, cols = (instance >= 0).nonzero(as_tuple=True)
    ids = instance[rows, cols]
    visible = torch.bincount(ids, minlength=count)[:count]
    big = torch.iinfo(torch.long).max
    lo_c = torch.full((count,), big).scatter_reduce(0, ids, cols, "amin")
    lo_r = torch.full((count,), big).scatter_reduce(0, ids, rows, "amin")
    hi_c = torch.full((count,), -1).scatter_reduce(0, ids, cols, "amax")
    hi_r = torch.full((count,), -1).scatter_reduce(0, ids, rows, "amax")
    box = torch.stack([lo_c, lo_r, hi_c, hi_r], 1)
    return visible, torch.where((visible > 0).unsqueeze(1), box, torch.full_like(box, -1))


def object_statistics(
    verts: Tensor,
    faces: Tensor,
    face_object: Tensor,
    count: int,
    instance: Tensor,
    intrinsics: Intrinsics,
    near_clip: float,
    raster_near: float,
    far: float,
    cull_backfaces: bool = False,
    occluders: Tensor | None = None,
) -> ObjectStats:
    """Statistics of ``count`` cars given their camera-frame meshes and the frame's instance map.

    Args:
        verts: ``(V, 3)`` camera-frame car vertices (all cars).
        faces: ``(F, 3)`` int64 faces into ``verts``; face_object ``(F,)`` the car of each face.
        count: number of cars N.
        instance: ``(H, W)`` int64 instance map of the full render (-1 none).
        intrinsics: the frame's camera.
        near_clip, raster_near, far, cull_backfaces: clipping plane and rasterizer settings of
            the main render (the same, so a car alone covers every pixel it covers in the scene).
        occluders: optional ``(M, 5)`` ``(umin, vmin, umax, vmax, zmin)`` screen boxes and nearest
            depth of every other surface that could hide a car (the scenery except the flat
            ground, which cannot hide anything standing on it). A car whose screen box meets no
            nearer box of an occluder or of another car cannot be occluded: its unoccluded count
            is its visible count and it is not drawn alone. Without them every car is drawn.
    """
    h, w = intrinsics.size
    visible, box = visible_boxes(instance, count)
    unoccluded = torch.zeros(count, dtype=torch.long)
    truncr = torch.zeros(count, dtype=torch.float64)
    drawn = (visible > 0).nonzero().squeeze(1)
    if drawn.numel():
        cverts, cfaces, parent = clip_near(verts, faces, near_clip)
        owner = face_object[parent]
        # Which drawn cars have projected vertices outside the frame (possibly truncated).
        z = cverts[:, 2].clamp(min=near_clip)
        u = cverts[:, 0] / z * intrinsics.fx + intrinsics.cx
        v = cverts[:, 1] / z * intrinsics.fy + intrinsics.cy
        fu, fv = u[cfaces].reshape(-1, 3), v[cfaces].reshape(-1, 3)
        big = torch.finfo(u.dtype).max
        umin = torch.full((count,), big).scatter_reduce(0, owner, fu.amin(1), "amin")
        vmin = torch.full((count,), big).scatter_reduce(0, owner, fv.amin(1), "amin")
        umax = torch.full((count,), -big).scatter_reduce(0, owner, fu.amax(1), "amax")
        vmax = torch.full((count,), -big).scatter_reduce(0, owner, fv.amax(1), "amax")
        outside = (umin < -0.5) | (vmin < -0.5) | (umax > w - 0.5) | (vmax > h - 0.5)
        warped = drawn[outside[drawn]]
        alone = drawn
        if occluders is not None:
            fz = cverts[:, 2][cfaces].reshape(-1, 3)
            zmin = torch.full((count,), big).scatter_reduce(0, owner, fz.amin(1), "amin")
            zmax = torch.full((count,), -big).scatter_reduce(0, owner, fz.amax(1), "amax")
            others = torch.stack([umin, vmin, umax, vmax, zmin], 1)
            hidden = _may_be_hidden(others[drawn], zmax[drawn], occluders.to(others.dtype))
            car_hit = _pairwise_hits(others[drawn], zmax[drawn], others)
            car_hit[torch.arange(drawn.numel()), drawn] = False  # a car does not hide itself
            clear = ~(hidden | car_hit.any(1))
            unoccluded[drawn[clear]] = visible[drawn[clear]]
            alone = drawn[~clear]

        # Per-car face lists, padded: the cars that may be occluded are drawn alone on a crop of
        # the frame around their in-frame box (exact pixel counts), the possibly truncated ones
        # once more on scaled canvases.
        slot = torch.full((count,), -1, dtype=torch.long)
        slot[drawn] = torch.arange(drawn.numel())
        keep = slot[owner] >= 0
        order = torch.argsort(owner[keep], stable=True)
        kfaces, kowner = cfaces[keep][order], owner[keep][order]
        per_car = torch.bincount(kowner, minlength=count)
        start = torch.cumsum(per_car, 0) - per_car
        rank = torch.arange(kowner.numel()) - start[kowner]
        padded = torch.zeros(count, int(per_car.max()), 3, dtype=torch.long)
        padded[kowner, rank] = kfaces
        K = intrinsics.matrix(torch.float64)

        if alone.numel():
            # The pixel rows / columns each car's projection can reach in the frame.
            c0 = torch.ceil(umin[alone].double() - 1e-6).clamp(0, w - 1).long()
            r0 = torch.ceil(vmin[alone].double() - 1e-6).clamp(0, h - 1).long()
            c1 = torch.floor(umax[alone].double() + 1e-6).clamp(0, w - 1).long()
            r1 = torch.floor(vmax[alone].double() + 1e-6).clamp(0, h - 1).long()
            for group in _size_groups((r1 - r0 + 1) * (c1 - c0 + 1)):
                ids = alone[group]
                crop_h, crop_w = int((r1 - r0)[group].max()) + 1, int((c1 - c0)[group].max()) + 1
                k_crop = K.repeat(ids.numel(), 1, 1)
                k_crop[:, 0, 2] -= c0[group].double()
                k_crop[:, 1, 2] -= r0[group].double()
                frags = rasterize_meshes(
                    cverts.unsqueeze(0).expand(ids.numel(), -1, -1),
                    padded[ids],
                    k_crop,
                    RasterSettings(
                        image_size=(crop_h, crop_w), near=raster_near, far=far, cull_backfaces=cull_backfaces
                    ),
                )
                # Canvas pixels beyond the frame's right / bottom edge do not count.
                in_w = torch.arange(crop_w).view(1, -1) + c0[group].view(-1, 1) < w
                in_h = torch.arange(crop_h).view(1, -1) + r0[group].view(-1, 1) < h
                covered = (frags.pix_to_mesh >= 0) & in_h.unsqueeze(2) & in_w.unsqueeze(1)
                unoccluded[ids] = covered.sum((1, 2))

        if warped.numel():
            ch, cw = _CANVAS
            bw = (umax[warped] - umin[warped]).double()
            bh = (vmax[warped] - vmin[warped]).double()
            s = torch.minimum(
                torch.ones_like(bw),
                torch.minimum(_FIT * cw / bw.clamp(min=1e-6), _FIT * ch / bh.clamp(min=1e-6)),
            )
            # u' = s u + o puts the box centre at the canvas centre: K' = diag(s, s, 1) K + offsets.
            o_u = (cw - 1) / 2 - s * (umin[warped] + umax[warped]).double() / 2
            o_v = (ch - 1) / 2 - s * (vmin[warped] + vmax[warped]).double() / 2
            k_fit = K.repeat(warped.numel(), 1, 1)
            k_fit[:, :2] *= s.view(-1, 1, 1)
            k_fit[:, 0, 2] += o_u
            k_fit[:, 1, 2] += o_v
            frags = rasterize_meshes(
                cverts.unsqueeze(0).expand(warped.numel(), -1, -1),
                padded[warped],
                k_fit,
                RasterSettings(image_size=(ch, cw), near=raster_near, far=far, cull_backfaces=cull_backfaces),
            )
            covered = frags.pix_to_mesh >= 0
            # Frame coordinates of canvas pixel centres, u = (u' - o) / s, inside [-0.5, W - 0.5]?
            fu = (torch.arange(cw, dtype=torch.float64).view(1, -1) - o_u.view(-1, 1)) / s.view(-1, 1)
            fv = (torch.arange(ch, dtype=torch.float64).view(1, -1) - o_v.view(-1, 1)) / s.view(-1, 1)
            fu_ok = (fu >= -0.5) & (fu <= w - 0.5)
            fv_ok = (fv >= -0.5) & (fv <= h - 0.5)
            inside = (covered & fv_ok.unsqueeze(2) & fu_ok.unsqueeze(1)).sum((1, 2))
            tot = covered.sum((1, 2))
            ratio = torch.where(
                tot > 0,
                1.0 - inside.double() / tot.clamp(min=1).double(),
                torch.ones_like(tot, dtype=torch.float64),
            )
            truncr[warped] = ratio.clamp(0.0, 1.0)
    return _ratios(visible, box, unoccluded, truncr)


def _ratios(visible: Tensor, box: Tensor, unoccluded: Tensor, truncr: Tensor) -> ObjectStats:
    """:class:`ObjectStats` with ``occupr`` (visible / inclusive box area) and ``visible_fraction``
    (visible / unoccluded) from ``(N,)`` counts and ``(N, 4)`` inclusive boxes (-1 rows for unseen objects)."""
    zero = torch.zeros(visible.shape[0], dtype=torch.float64)
    area = (box[:, 2] - box[:, 0] + 1) * (box[:, 3] - box[:, 1] + 1)
    occupr = torch.where(visible > 0, visible.double() / area.clamp(min=1).double(), zero).clamp(0.0, 1.0)
    fraction = torch.where(unoccluded > 0, visible.double() / unoccluded.clamp(min=1).double(), zero).clamp(0.0, 1.0)
    return ObjectStats(visible.numpy(), box.numpy(), unoccluded.numpy(), truncr.numpy(), occupr.numpy(),
                       fraction.numpy())
