"""Filling the pixels an edit vacated (the photo appearance's step 2: :mod:`sdn3d.editing.photo`): the hole, and
Telea / PatchMatch / the generator's picture in it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.editing.photo.settings import (
    AUTO_THIN_PX,
    PATCHMATCH_MAX_SIDE,
    RAY_FILLS,
    PhotoSettings,
    PhotoSettingsError,
)
from sdn3d.image_ops import (
    any_along,
    any_set,
    count_set,
    dilate_square,
    ids_present,
    isin_ids,
    nonzero_yx,
    padded_window,
)

if TYPE_CHECKING:
    from sdn3d.editing.photo.road import PictureLab

__all__ = ["inpaint", "vacated_hole", "leftover_pieces", "shadow_pieces", "relight_faint_shadow", "fill_hole",
           "RemovalGuides", "removal_guides"]


def inpaint(image: Tensor, hole: Tensor, method: str = "telea", radius: int = 5, patch_size: int = 3,
            keep_out: Tensor | None = None, max_side: int = PATCHMATCH_MAX_SIDE) -> Tensor:
    """``image (3, H, W)`` float in [0, 1] with ``hole (H, W)`` filled, each connected part of the hole on its own
    bounding box plus a margin (:func:`_inpaint_part`; ``method`` there, or ``'auto'``); PatchMatch works on crops
    at most ``max_side`` pixels on a side (its time grows with their area)."""
    import cv2

    if not any_set(hole):
        return image
    count, labels = cv2.connectedComponents(hole.numpy().astype(np.uint8), connectivity=8)
    depth = cv2.distanceTransform(hole.numpy().astype(np.uint8), cv2.DIST_L2, 3) if method == "auto" else None
    labels = torch.from_numpy(labels)
    for k in range(1, count):
        part = labels == k
        how = method
        if method == "auto":  # thin gaps smear little under Telea; large holes need copied texture
            how = "telea" if float(depth[part.numpy()].max()) <= AUTO_THIN_PX else "patchmatch"
        image = _inpaint_part(image, part, how, radius, patch_size, keep_out, max_side)
    return image


def _inpaint_part(image: Tensor, hole: Tensor, method: str, radius: int, patch_size: int,
                  keep_out: Tensor | None, max_side: int = PATCHMATCH_MAX_SIDE) -> Tensor:
    """:func:`inpaint` of one connected ``hole`` on its box plus a margin (padded by one pixel: OpenCV mishandles
    holes that touch the top or left edge).

    Args:
        method: ``'telea'`` (OpenCV's fast marching; smears large holes), ``'patchmatch'`` (PyPatchMatch: copies
            patches of the surroundings; plausible road and kerb texture, slower) or ``'auto'`` (per connected part:
            Telea where it is thin, :data:`AUTO_THIN_PX`, else PatchMatch).
        radius: Telea's neighbourhood; patch_size: PatchMatch's patch radius.
        keep_out: ``(H, W)`` pixels PatchMatch must not copy from (other objects).
    """
    import cv2

    height, width = hole.shape
    ys, xs = nonzero_yx(hole)
    margin = max(4 * radius + 8, (int(ys.max()) - int(ys.min()) + int(xs.max()) - int(xs.min())) // 2 + 8) \
        if method == "patchmatch" else 4 * radius + 8
    x0, x1 = max(int(xs.min()) - margin, 0), min(int(xs.max()) + margin + 1, width)
    y0, y1 = max(int(ys.min()) - margin, 0), min(int(ys.max()) + margin + 1, height)
    crop = (image[:, y0:y1, x0:x1].permute(1, 2, 0).clamp(0, 1).numpy() * 255 + 0.5).astype(np.uint8)
    mask = hole[y0:y1, x0:x1].numpy().astype(np.uint8)
    crop = cv2.copyMakeBorder(crop, 1, 1, 1, 1, cv2.BORDER_REPLICATE)
    # The pad continues the hole too: a padded pixel beside a hole pixel is no known value to fill from.
    mask = cv2.copyMakeBorder(mask, 1, 1, 1, 1, cv2.BORDER_REPLICATE)
    if method == "patchmatch":
        from patchmatch import patch_match

        avoid = None
        if keep_out is not None and any_set(keep_out[y0:y1, x0:x1]):
            avoid = cv2.copyMakeBorder((keep_out[y0:y1, x0:x1] & ~hole[y0:y1, x0:x1]).numpy().astype(np.uint8),
                                       1, 1, 1, 1, cv2.BORDER_CONSTANT, value=0)
        full = crop.shape[1], crop.shape[0]
        shrink = min(1.0, max_side / max(full))
        if shrink < 1.0:  # a large hole: fill at a coarser scale (its time grows with the crop's area)
            small = max(round(full[0] * shrink), 8), max(round(full[1] * shrink), 8)
            crop_s = cv2.resize(crop, small, interpolation=cv2.INTER_AREA)
            mask_s = cv2.resize(mask, small, interpolation=cv2.INTER_NEAREST) | (cv2.resize(
                mask.astype(np.float32), small, interpolation=cv2.INTER_AREA) > 0).astype(np.uint8)
            avoid_s = None if avoid is None else cv2.resize(avoid, small, interpolation=cv2.INTER_NEAREST) & ~mask_s
            filled = cv2.resize(patch_match.inpaint(crop_s, mask_s, global_mask=avoid_s, patch_size=patch_size),
                                full, interpolation=cv2.INTER_LINEAR)
        else:
            filled = patch_match.inpaint(np.ascontiguousarray(crop), mask, global_mask=avoid, patch_size=patch_size)
        filled = filled[1:-1, 1:-1]
    elif method == "telea":
        filled = cv2.inpaint(np.ascontiguousarray(crop[:, :, ::-1]), mask, radius, cv2.INPAINT_TELEA)[1:-1, 1:-1, ::-1]
    else:
        raise PhotoSettingsError(f"inpaint method must be 'telea', 'patchmatch' or 'auto', got {method!r}")
    out = image.clone()
    patch = torch.from_numpy(np.ascontiguousarray(filled)).permute(2, 0, 1).float() / 255
    region = hole[y0:y1, x0:x1]
    out[:, y0:y1, x0:x1] = torch.where(region[None], patch, out[:, y0:y1, x0:x1])
    return out


def vacated_hole(ids: Tensor, gone: Tensor, keep: Tensor, settings: PhotoSettings) -> Tensor:
    """``(H, W)`` bool pixels to fill: those of ``ids (H, W)`` (instance map) in ``gone (K,)`` (moved or deleted
    objects), grown by ``hole_dilate_px`` and by a band below each (its old contact shadow), less ``keep (H, W)``
    (pixels of objects that stay)."""
    vacated = isin_ids(ids, gone) & (ids != 0)
    hole = dilate_square(vacated, settings.hole_dilate_px)
    if settings.shadow_band > 0 and any_set(vacated):
        hole |= dilate_square(_shadow_bands(ids, gone, settings.shadow_band), 1)
    return hole & ~keep


#: :func:`leftover_pieces`: an object whose reach (``reach`` of its mask's height) is under this many pixels is not
#: searched: its mirrors are a pixel or less, which the hole's rim (``hole_dilate_px``) covers, and what a reach that
#: short cuts off is the lines along the hole's edge (an anti-aliased rim, a rail's edge).
LEFTOVER_MIN_PX = 3


def leftover_pieces(lab: PictureLab, hole: Tensor, ids: Tensor, gone: Tensor, blocked: Tensor, reach: float,
                    step: float, attach_px: int = 4) -> Tensor:
    """``(H, W)`` bool: pieces of the removed objects that their masks and fitted silhouettes missed (a side mirror
    juts out of both: a template has none, and a mask made at the working size loses its thin stalk), which the hole
    must take too, else the fill runs up to them and they stay in the picture as flecks.

    Per object of ``gone (K,)`` in ``ids (H, W)`` (the instance map), with ``r`` = ``reach`` of its mask's height
    (rounded; under :data:`LEFTOVER_MIN_PX` the object is not searched): the *zone* is the pixels at most ``r + 1``
    from ``hole (H, W)`` (a square's), outside it and outside ``blocked (H, W)`` (objects that stay, thin things in
    front of the car). It is flooded from its outer edge (its pixels ``r + 1`` from the hole), pixel to 8-neighbour
    wherever their colours (``lab``, the picture's :class:`~sdn3d.editing.photo.road.PictureLab`) differ by at most
    ``step`` in each Lab channel (OpenCV's ``floodFill``, floating range). What the flood reaches runs on from beyond
    ``r``: road, a verge, a pole, a lane line, and stays. What it does not reach lies within ``r`` of the hole, cut off
    from everything farther by a colour edge. Its 8-connected pieces that touch the hole within ``attach_px`` pixels of
    the object's own mask (attached to the car, not only to the shadow band below it) and lie beside its upper half
    (reaching lower than ``r`` rows below the mask's top row and higher than its middle row: wholly above the roof is
    what stands behind the car, a kerb cut off between two poles; lower down, what lies on the road beside the shadow
    band, a lane line) are leftovers, grown by a pixel within ``r`` of the hole (their anti-aliased rim). ``reach`` 0:
    none.
    """
    import cv2

    out = torch.zeros_like(hole)
    if reach <= 0 or not any_set(hole):
        return out
    height, width = hole.shape
    gone = gone[ids_present(ids, gone)] if len(gone) else gone
    for iid in gone.tolist():
        mine = ids == iid
        rows, cols = any_along(mine, 1).nonzero().flatten(), any_along(mine, 0).nonzero().flatten()
        r = round(reach * float(rows[-1] - rows[0] + 1))
        if r < LEFTOVER_MIN_PX:
            continue
        # The object's box grown by what its silhouette and shadow band may add to the hole, and the zone.
        pad = 2 * r + 16
        y0, y1, x0, x1 = padded_window(rows, cols, pad, (height, width))
        near_hole = hole[y0:y1, x0:x1]
        within_r = dilate_square(near_hole, r)
        zone = dilate_square(near_hole, r + 1) & ~near_hole & ~blocked[y0:y1, x0:x1]
        if not any_set(zone & within_r):
            continue
        picture = np.ascontiguousarray(lab.box(y0, y1, x0, x1).view(y1 - y0, x1 - x0, 3).numpy())
        # floodFill's mask: 0 where it may fill (the zone), 1 elsewhere; it writes 2 where it filled.
        fill = np.pad((~zone).numpy().astype(np.uint8), 1, constant_values=1)
        flags = 8 | cv2.FLOODFILL_MASK_ONLY | (2 << 8)
        ey, ex = nonzero_yx(zone & ~within_r)
        for y, x in zip(ey.tolist(), ex.tolist(), strict=True):
            if fill[y + 1, x + 1] == 0:
                cv2.floodFill(picture, fill, (x, y), 0, (step,) * 3, (step,) * 3, flags)
        cut_off = torch.from_numpy(fill[1:-1, 1:-1] == 0) & zone
        if not any_set(cut_off):
            continue
        _, labels = cv2.connectedComponents(cut_off.numpy().astype(np.uint8), connectivity=8)
        labels = torch.from_numpy(labels).long()
        attached = dilate_square(near_hole, 1) & dilate_square(mine[y0:y1, x0:x1], attach_px) & cut_off
        touching = labels[attached].unique()
        touching = touching[touching > 0]
        # Beside the car's upper half, where a mirror juts out: cut off wholly above the roof is what stands behind
        # it (a kerb between two poles), and lower down it lies on the road (a lane line beside the shadow band).
        at_row = torch.arange(y0, y1)[:, None].expand(-1, x1 - x0).flatten()
        lowest = torch.zeros(int(labels.max()) + 1, dtype=torch.long).scatter_reduce(
            0, labels.flatten(), at_row, "amax")
        highest = torch.full_like(lowest, height).scatter_reduce(0, labels.flatten(), at_row, "amin")
        touching = touching[(lowest[touching] > int(rows[0]) + r)
                            & (highest[touching] <= (int(rows[0]) + int(rows[-1])) // 2)]
        if len(touching):
            out[y0:y1, x0:x1] |= dilate_square(isin_ids(labels, touching), 1) & zone & within_r
    return out


def shadow_pieces(dark: Tensor, hole: Tensor, reach: float, ground: float) -> Tensor:
    """``(H, W)`` bool: the removed objects' shadow that runs on past the hole's edge where the region it was looked
    for misses it (that region comes from the fitted box, which can sit off the car: on the real frame of
    ``tests/data`` the red car's box lies below its wheels, and the shadow's tip left of its rear wheel stayed).

    Per 8-connected part of ``hole (H, W)``, with ``r`` = ``reach`` of its height (rounded; under
    :data:`LEFTOVER_MIN_PX` the part is not searched): the 8-connected pieces of ``dark (H, W)`` (shadowed road,
    :func:`~sdn3d.editing.photo.road.shadowed_road`) outside the hole that touch a ``dark`` pixel of the part (the
    shadow the hole covers, running on across its edge), lie wholly in its ground rows (from ``ground`` of its
    height below its top row down: higher up, dark road-coloured pixels are far road in shade) and wholly within
    ``r`` of it (a square's). A tree's or a building's shadow, a dark patch or another car running on beyond ``r``
    stays, and so does a dark thing beside a lit edge of the hole. ``reach`` 0: none."""
    import cv2

    out = torch.zeros_like(hole)
    if reach <= 0 or not any_set(hole) or not any_set(dark):
        return out
    height, width = hole.shape
    count, parts = cv2.connectedComponents(hole.numpy().astype(np.uint8), connectivity=8)
    parts = torch.from_numpy(parts)
    for k in range(1, count):
        part = parts == k
        rows, cols = any_along(part, 1).nonzero().flatten(), any_along(part, 0).nonzero().flatten()
        r = round(reach * float(rows[-1] - rows[0] + 1))
        if r < LEFTOVER_MIN_PX:
            continue
        # The part's box grown past r: a piece that reaches the box's edge runs on beyond r and is left out below.
        pad = r + 2
        y0, y1, x0, x1 = padded_window(rows, cols, pad, (height, width))
        mine, shade = part[y0:y1, x0:x1], dark[y0:y1, x0:x1]
        candidate = shade & ~hole[y0:y1, x0:x1]
        if not any_set(candidate):
            continue
        n, labels = cv2.connectedComponents(candidate.numpy().astype(np.uint8), connectivity=8)
        labels = torch.from_numpy(labels).long()
        touching = labels[dilate_square(mine & shade, 1) & candidate].unique()
        touching = touching[touching > 0]
        if not len(touching):
            continue
        cut = int(rows[0]) + int(ground * float(rows[-1] - rows[0]))
        outside = ~dilate_square(mine, r)
        outside[: max(cut - y0, 0)] = True
        # A piece with any pixel above the ground rows or past r (the box's rim included) runs on: it stays.
        runs_on = torch.zeros(n, dtype=torch.bool)
        runs_on[labels[outside & candidate].unique()] = True
        touching = touching[~runs_on[touching]]
        if len(touching):
            out[y0:y1, x0:x1] |= isin_ids(labels, touching)
    return out


def _shadow_bands(ids: Tensor, gone: Tensor, share: float) -> Tensor:
    """``(H, W)`` bool: the pixels at most ``band`` rows below a pixel of an object of ``gone`` in ``ids``, ``band``
    being ``share`` of that object's height (at least 1), all objects in one pass: a running count of each
    object's pixels down every column, differenced ``band + 1`` rows apart."""
    gone = gone[ids_present(ids, gone)] if len(gone) else gone
    if not len(gone):
        return torch.zeros_like(ids, dtype=torch.bool)
    # The bands lie in the objects' columns, from their top row down: worked out there (no pixel of theirs above).
    theirs = isin_ids(ids, gone)
    cols = any_along(theirs, 0).nonzero().flatten()
    y0, x0, x1 = int(any_along(theirs, 1).nonzero()[0]), int(cols[0]), int(cols[-1]) + 1
    out = torch.zeros_like(ids, dtype=torch.bool)
    out[y0:, x0:x1] = _bands_in(ids[y0:, x0:x1], gone, share)
    return out


def _bands_in(ids: Tensor, gone: Tensor, share: float) -> Tensor:
    """:func:`_shadow_bands` on a window holding all the pixels of ``gone`` (each present)."""
    height = ids.shape[0]
    one = ids[None] == gone[:, None, None]  # (K, H, W)
    rows = one.any(2)  # (K, H)
    at = torch.arange(height)
    top = torch.where(rows, at, height).amin(1)
    bottom = torch.where(rows, at, -1).amax(1)
    bands = torch.tensor([max(1, round(share * float(b - t + 1))) for t, b in zip(top.tolist(), bottom.tolist(),
                                                                                 strict=True)])
    count = F.pad(one.to(torch.int32).cumsum(1), (0, 0, 1, 0))  # (K, H + 1, W): pixels in rows < i
    start = (at[None] - bands[:, None]).clamp(min=0)  # (K, H): the first row of each pixel's window
    index = start[:, :, None].expand(-1, -1, ids.shape[1])
    return ((count[:, 1:] - count.gather(1, index)) > 0).any(0)


def fill_hole(image: Tensor, hole: Tensor, settings: PhotoSettings, keep_out: Tensor | None = None,
              fill: Tensor | None = None, vanishing: tuple[float, float] | None = None,
              road: Tensor | None = None, ground_row: float | None = None,
              lab: PictureLab | None = None) -> Tensor:
    """``image (3, H, W)`` with ``hole`` filled by ``settings.fill`` (:data:`FILL_METHODS`; ``fill (3, H, W)``: the
    generator's picture at this size, for ``'generator'``); ``keep_out``: pixels PatchMatch and the rays must not
    copy; ``vanishing``: the road's vanishing point ``(u, v)`` for ``'rays'`` (:func:`~sdn3d.editing.photo.road.
    ray_fill`; None: the picture's centre row and column, a level camera looking down the road); ``'learnt'``: the
    rays' fill with the net's correction inside the hole (:func:`~sdn3d.editing.photo.learnt.learnt_fill`); ``road
    (3,)``: the road's CIE Lab around the hole, which tells the rays' road from a verge on the ground, the rows from
    ``ground_row`` down (``settings.ray_verge``; None: the rays blend them); ``lab``: ``image``'s
    :class:`~sdn3d.editing.photo.road.PictureLab` for the rays' road tests (None: converted here)."""
    if not any_set(hole):
        return image.clone()
    if settings.fill == "generator":
        if fill is None:
            raise PhotoSettingsError("photo.fill=generator needs the generator's picture (the textural branch)")
        return torch.where(hole[None], fill.clamp(0, 1).to(image.dtype), image)
    if settings.fill in RAY_FILLS:
        from sdn3d.editing.photo.road import ray_fill

        height, width = hole.shape
        vp = vanishing if vanishing is not None else ((width - 1) / 2, (height - 1) / 2)
        out, reached = ray_fill(image, hole, vp, keep_out, settings.ray_blur, settings.ray_texture, settings.ray_span,
                                 match_grain=settings.ray_grain == "match", marks=settings.ray_marks,
                                 haze=settings.ray_haze, airlight=settings.ray_haze_airlight,
                                 road=None if ground_row is None else road, verge=settings.ray_verge,
                                 ground_row=0.0 if ground_row is None else ground_row, lab=lab,
                                 vanishing=settings.ray_vanishing)
        rest = hole & ~reached  # no ray reaches these (or none has a far side): Telea from what is known around them
        out = inpaint(out, rest, "telea", settings.inpaint_radius) if any_set(rest) else out
        if settings.fill == "learnt":
            from sdn3d.editing.photo.learnt import learnt_fill, load_fill_net

            out = learnt_fill(out, hole, load_fill_net(settings.learnt_weights), keep_out)
        return out
    return inpaint(image, hole, settings.fill, settings.inpaint_radius, keep_out=keep_out)


@dataclass(frozen=True)
class RemovalGuides:
    """The 2D parts of a removal, which need no fitted 3D (:func:`removal_guides`): what of the removed objects their
    hole missed, and where the road's lines meet.

    Attributes:
        leftovers: ``(H, W)`` bool, :func:`leftover_pieces` of the removed objects (filled after the hole, by Telea:
            :meth:`fill_leftovers`).
        vanishing: ``(u, v)`` the road's vanishing point for the rays (:func:`fill_hole`'s ``vanishing``), or None
            where the fill is no ray fill or nothing was removed.
    """

    leftovers: Tensor
    vanishing: tuple[float, float] | None

    def fill_leftovers(self, filled: Tensor, settings: PhotoSettings) -> Tensor:
        """``filled (3, H, W)`` (the picture with the hole filled) with :attr:`leftovers` filled by Telea from it: after
        the hole, so that the hole's own fill stays what it was (its rays, their grain and haze are fitted on the
        pixels around the hole)."""
        return inpaint(filled, self.leftovers, "telea", settings.inpaint_radius) if any_set(self.leftovers) else filled


def removal_guides(image: Tensor, K: Tensor, lab: PictureLab, hole: Tensor, ids: Tensor, gone: Tensor,
                   blocked: Tensor, settings: PhotoSettings, ry: float | None = None) -> RemovalGuides:
    """The 2D parts of removing the objects ``gone (K,)`` of ``ids (H, W)`` (the instance map) from ``image (3, H,
    W)`` (``lab``: its :class:`~sdn3d.editing.photo.road.PictureLab`, ``K (3, 3)``: its camera), one home for
    3D-SDN's removal (:func:`~sdn3d.editing.photo.transfer.render_photo`) and the 2D baselines'
    (:func:`sdn3d.evaluation.baselines.baseline_photos`), so that Table 1 compares their 3D parts and not these.

    - ``leftovers``: :func:`leftover_pieces` of ``hole (H, W)`` (the vacated pixels before anything in front is put
      back over them), ``blocked (H, W)`` (objects that stay, thin things in front), ``settings.leftover_reach`` and
      ``settings.leftover_step``.
    - ``vanishing`` (``settings.fill`` a ray fill, something removed):
      :func:`~sdn3d.editing.photo.road.removal_vanishing_point` of the removed objects' pixels: the picture's edges
      around them, else the yaw ``ry`` (3D-SDN: the first removed car's fitted one; None without 3D), else the
      camera's forward direction (``K``'s principal point for a level camera, not the picture's centre).
    """
    from sdn3d.editing.photo.road import removal_vanishing_point

    leftovers = leftover_pieces(lab, hole, ids, gone, blocked, settings.leftover_reach, settings.leftover_step)
    vanishing = None
    if settings.fill in RAY_FILLS and bool(gone.numel()):
        objects_px = ids != 0
        vanishing = removal_vanishing_point(image, K, isin_ids(ids, gone) & objects_px, objects_px, ry)
    return RemovalGuides(leftovers, vanishing)


# -- removal with its effects (shadow relit, road filled from road) ------------------------------------------------


def _shadow_fit(image: Tensor, search: Tensor, lit: Tensor, road: Tensor, tolerance: float = 12.0):
    """``(gain (3,) float64, y (H, W), y_lit, y_core, shadow pixels (H, W))`` of the shadow inside ``search`` (module
    doc of :func:`relight_shadow`), or None where too few lit road or shadow pixels are found."""
    from sdn3d.editing.photo.road import road_like
    from sdn3d.image_ops import luminance

    like = road_like(image, road, tolerance, within=search | lit)
    flat = image.permute(1, 2, 0).reshape(-1, 3).double()
    y = luminance(flat).view(search.shape)
    lit_pix = (lit & like).view(-1)
    if count_set(lit_pix) < 30:
        return None
    y_lit = float(y.view(-1)[lit_pix].median())
    cand = search & like & (y < 0.85 * y_lit)
    if count_set(cand) < 20:
        return None
    yc = y[cand]
    core_cut = float(torch.quantile(yc, 0.25))
    core = cand & (y <= core_cut)
    lit_rgb = flat[lit_pix].median(0).values
    sh_rgb = flat[core.view(-1)].median(0).values.clamp(min=0.01)
    gain = (lit_rgb / sh_rgb).clamp(1.0, 8.0)
    return gain, y, y_lit, float(luminance(sh_rgb)), cand


def relight_faint_shadow(image: Tensor, shade: Tensor, zone: Tensor, touch: Tensor, upper: float,
                         floor: float, sigma: float = 1.5) -> tuple[Tensor, Tensor]:
    """``(image, gain (H, W) float32)``: the faint edge of a removed car's shadow relit. A car's shadow fades out
    through a penumbra and the skylight it blocks (a few per cent darker than the road, ~0.9 of the row's lit road on
    the tuning trees' deletes), which a shadow test at ``shadow_light`` (0.8) leaves in the picture: a grey halo
    around the filled hole, and darker road that the rays carry into it.

    ``shade (H, W)``: each road pixel's luma over the lit road's (:func:`~sdn3d.editing.photo.road.road_shade`
    with ``luma``; NaN off the road), blurred by ``sigma`` pixels over the road pixels (so a gain follows the
    shadow's soft edge, not the road's grain, and the texture stays); the faint shadow is the road pixels of ``zone
    (H, W)`` whose blurred share is under ``upper``, in 8-connected pieces touching ``touch (H, W)`` (the hole and
    the shadow filled with it: the car's shadow runs on from there; a dark patch apart from it stays). Each of their
    pixels is multiplied by one over its blurred share (at most ``1 / floor``), that gain blurred once more by
    ``sigma`` so no seam shows where it ends; the gain is 1 elsewhere."""
    import cv2

    from sdn3d.editing.photo.road import _normalised_blur

    ones = torch.ones(tuple(zone.shape), dtype=torch.float32)
    road = torch.isfinite(shade)
    if not any_set(zone & road) or not any_set(touch):
        return image, ones
    both = zone | touch
    rows, cols = any_along(both, 1).nonzero().flatten(), any_along(both, 0).nonzero().flatten()
    y0, y1, x0, x1 = padded_window(rows, cols, int(3 * sigma) + 2, tuple(zone.shape))
    values = torch.nan_to_num(shade[y0:y1, x0:x1], nan=0.0).float()
    blurred = _normalised_blur(values[None], road[y0:y1, x0:x1], sigma)[0]
    mine = zone[y0:y1, x0:x1] & road[y0:y1, x0:x1]
    faint = mine & (blurred < upper)
    if not any_set(faint):
        return image, ones
    count, labels = cv2.connectedComponents(faint.numpy().astype(np.uint8), connectivity=8)
    labels = torch.from_numpy(labels).long()
    near = labels[dilate_square(touch[y0:y1, x0:x1], 1) & faint].unique()
    near = near[near > 0]
    if not len(near):
        return image, ones
    faint = isin_ids(labels, near)
    gain = torch.where(faint, 1.0 / blurred.clamp(min=floor), torch.ones_like(blurred)).clamp(min=1.0)
    gain = torch.from_numpy(cv2.GaussianBlur(gain.float().numpy(), (0, 0), sigma))
    gain = torch.where(mine, gain, torch.ones_like(gain))
    out_gain = ones.clone()
    out_gain[y0:y1, x0:x1] = gain
    return (image * out_gain[None].to(image.dtype)).clamp(0, 1), out_gain


def shadow_gain(image: Tensor, search: Tensor, lit: Tensor, road: Tensor, tolerance: float = 12.0) -> Tensor | None:
    """``(3,)`` float64 per-channel gain lit road / shadow core of the shadow inside ``search`` (as
    :func:`relight_shadow` measures it), None where no shadow is found."""
    fit = _shadow_fit(image, search, lit, road, tolerance)
    return None if fit is None else fit[0]


def relight_shadow(image: Tensor, search: Tensor, lit: Tensor, road: Tensor, strength: float = 1.0,
                   tolerance: float = 12.0) -> tuple[Tensor, Tensor]:
    """``(image, matte (H, W))``: the shadow inside ``search (H, W)`` relit (Le & Samaras 2019: a per-channel gain
    and a matte, so the road's texture stays): lit road is the median of ``lit (H, W)`` pixels that look like road
    (:func:`~sdn3d.editing.photo.road.road_like` of ``road``, Lab); shadow pixels are road-like pixels of ``search``
    darker than 0.85 of it; the gain per channel is lit over the shadow's core (its darkest quarter's median), the
    matte each pixel's share of that darkening (0 lit, 1 core), blurred; ``image * (1 + matte * (gain - 1))``."""
    import cv2

    zero = torch.zeros_like(search, dtype=torch.float32)
    fit = _shadow_fit(image, search, lit, road, tolerance)
    if fit is None:
        return image, zero
    gain, y, y_lit, y_core, cand = fit
    matte = ((y_lit - y) / max(y_lit - y_core, 1e-3)).clamp(0, 1) * cand
    matte = torch.from_numpy(cv2.GaussianBlur(matte.float().numpy(), (0, 0), 1.0)) * search
    matte = matte * strength
    out = image * (1 + matte[None] * (gain.float()[:, None, None] - 1))
    return out.clamp(0, 1), matte
