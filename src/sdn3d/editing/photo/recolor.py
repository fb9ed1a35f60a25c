"""Repainting a car's body in CIE Lab (the photo appearance's step 5: :mod:`sdn3d.editing.photo`), and finding its
paint among its pixels (also the light fit's pixels).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import torch
from torch import Tensor

from sdn3d.editing.ops import SetCode
from sdn3d.image_ops import padded_window

__all__ = ["paints", "body_pixels", "body_paint", "ground_in_mask", "recolor_pixels", "registered_tyres",
           "srgb_to_lab", "DARK_PAINT_LIFT", "DARK_PAINT_L", "RIM_SHARE", "RIM_CHROMA", "TYRE_MIN_PX",
           "RIM_MIN_HEIGHT", "RIM_MAX_HEIGHT", "RIM_MIN_WIDTH", "RIM_MIN_AREA", "RIM_MIN_FILL"]


def paints(ops: Sequence[object]) -> dict[int, tuple[float, float, float]]:
    """``{instance id: sRGB paint}`` of the :class:`~sdn3d.editing.ops.SetCode` ops in ``ops`` that name a colour
    (the last one wins)."""
    return {int(op.instance_id): op.color for op in ops if isinstance(op, SetCode) and op.color is not None}


def _paint(lab: Tensor, chroma_tol: float = 15.0, dark_ratio: float = 0.45) -> Tensor:
    """``(P,)`` bool: the car's paint among its pixels ``lab (P, 3)``: the largest colour cluster
    (:func:`_kmeans_lab`) sets the paint's chroma and lightness; paint is brighter than ``dark_ratio`` of that
    lightness and, for a coloured car, of the same hue (within 30 degrees, chroma at least 0.3 of it: shade lowers
    chroma, not hue), for a grey one within ``chroma_tol`` of its chroma (a, b). Windows and tyres (much darker)
    and lights (another hue) are not paint."""
    assign = _kmeans_lab(lab)
    core = lab[assign == int(torch.bincount(assign).argmax())]
    chroma, light = core[:, 1:].mean(0), core[:, 0].mean()
    bright = lab[:, 0] > dark_ratio * light
    size = float(chroma.norm())
    if size <= 2 * chroma_tol / 3:  # grey, white, black or silver paint: near that chroma
        return ((lab[:, 1:] - chroma).norm(dim=1) < chroma_tol) & bright
    # Coloured paint: the same hue (shade lowers chroma and lightness but keeps the hue), and not greyish.
    ab = lab[:, 1:]
    cosine = (ab @ chroma) / (ab.norm(dim=1) * size).clamp(min=1e-6)
    return (cosine > math.cos(math.radians(30))) & (ab.norm(dim=1) > 0.3 * size) & bright


def body_pixels(colors: Tensor, groups: Tensor) -> Tensor:
    """``(P,)`` bool: the paint (:func:`_paint`) among the pixels of each group (object) of ``colors (P, 3)``."""
    body = torch.zeros(len(colors), dtype=torch.bool)
    for g in groups.unique().tolist():
        sel = (groups == g).nonzero().flatten()
        if len(sel) < 8:
            continue
        body[sel[_paint(srgb_to_lab(colors[sel]))]] = True
    return body


def _kmeans_lab(lab: Tensor, k: int = 3, iters: int = 10) -> Tensor:
    """``(P,)`` cluster of each ``lab (P, 3)`` row; deterministic (centres start at lightness quantiles)."""
    q = torch.quantile(lab[:, 0], torch.linspace(0.15, 0.85, k, dtype=lab.dtype))
    centres = torch.stack([lab[(lab[:, 0] - qi).abs().argmin()] for qi in q])
    assign = torch.zeros(len(lab), dtype=torch.long)
    for _ in range(iters):
        assign = torch.cdist(lab, centres).argmin(1)
        for c in range(k):
            sel = assign == c
            if bool(sel.any()):
                centres[c] = lab[sel].mean(0)
    return assign


def body_paint(lab: Tensor, min_chroma: float = 10.0, hue_deg: float = 40.0,
               reference: Tensor | None = None) -> tuple[Tensor, bool]:
    """``(paint (P,) bool, coloured)`` among pixels ``lab (P, 3)`` of a car's *body part* (the fitted mesh says
    which pixels are paint, so no cluster has to): the chroma-weighted mean hue is the paint's; a coloured paint
    (a body whose median chroma is at least ``min_chroma``) keeps the pixels within ``hue_deg`` of it and at least
    0.25 of its median chroma (windows, tyres and grey trim seen
    through a loosely fitted mesh are not paint); a grey, black, white or silver paint keeps every pixel within
    ``min_chroma`` of grey. ``reference (R, 3)``: the body pixels that set the paint's hue and chroma, when ``lab``
    holds other pixels too (default: ``lab`` itself)."""
    ab = lab[:, 1:]
    chroma = ab.norm(dim=1)
    ref_ab = ab if reference is None else reference[:, 1:]
    ref_chroma = ref_ab.norm(dim=1)
    mean = (ref_ab * ref_chroma[:, None]).sum(0) / ref_chroma.sum().clamp(min=1e-6)
    ref = float(ref_chroma.median())
    if float(mean.norm()) < min_chroma or ref < min_chroma:  # most of the body is grey: a few coloured pixels
        # (a tail lamp, a reflection) do not make a black car red
        return chroma < 1.5 * min_chroma, False
    cosine = (ab @ mean) / (chroma * mean.norm()).clamp(min=1e-6)
    return (cosine > math.cos(math.radians(hue_deg))) & (chroma > 0.25 * ref), True


#: :func:`recolor_pixels` with ``body_part``: a pixel of a grey or black body more than this much lighter (CIE L*)
#: than the paint's median is not paint when the paint is dark (median L* below :data:`DARK_PAINT_L`): a rim, grey
#: trim, lit road or a reflection of the sky on black paint (a reflection keeps its colour on any paint). On the real
#: frame in ``tests/data`` the black car's rims and grey diffuser turned light blue.
DARK_PAINT_LIFT = 25.0
#: Median CIE L* below which a grey paint is dark (:data:`DARK_PAINT_LIFT`).
DARK_PAINT_L = 30.0


def ground_in_mask(image: Tensor, mask: Tensor, reach: int = 6, band: float = 0.35, tol: float = 2.5) -> Tensor:
    """``(H, W)`` bool: the road a car's ``mask (H, W)`` took in along its lower edge in ``image (3, H, W)`` sRGB in
    [0, 1]: the lit road and the car's shadow under its sills and bumpers, which a box's mask holds as dark as black
    paint (recolour must leave them: the black car of the real frame in ``tests/data`` got a blue wedge there).

    The road is read off the picture just below the mask (``reach`` pixels under its lower edge): its darker and
    lighter halves (shadow and lit road) each give a colour, and a mask pixel is road when its Lab is within
    ``max(tol, 2.5 x`` that half's median spread ``)`` of one of them, it lies in the mask's lowest ``band`` of its
    height (counted up from the mask's lowest pixel in its column), and it is connected (4-neighbours) through such
    pixels to a pixel at the mask's edge. A black car's body and sills are darker than its shadow on the road (their
    own shade, no sky) and its tyres are rubber and grey rims: a shadow grown by colour stops at them."""
    import cv2

    height, width = mask.shape
    out = torch.zeros_like(mask)
    rows, cols = mask.any(1).nonzero().flatten(), mask.any(0).nonzero().flatten()
    if not len(rows):
        return out
    pad = reach + 1
    y0, y1, x0, x1 = padded_window(rows, cols, pad, (height, width))
    m = mask[y0:y1, x0:x1]
    lab = srgb_to_lab(image[:, y0:y1, x0:x1].permute(1, 2, 0).reshape(-1, 3)).view(y1 - y0, x1 - x0, 3)
    below = torch.zeros_like(m)  # up to `reach` pixels under a mask pixel, outside the mask
    for k in range(1, reach + 1):
        below[k:] |= m[:-k]
    below &= ~m
    ref = lab[below]
    if len(ref) < 20:
        return out
    light = ref[:, 0]
    cut = 0.5 * (torch.quantile(light, 0.1) + torch.quantile(light, 0.9))
    centres, tols = [], []
    for half in (light < cut, light >= cut):
        if int(half.sum()) >= 10:
            centre = ref[half].median(0).values
            centres.append(centre)
            tols.append(max(tol, 2.5 * float((ref[half] - centre).norm(dim=1).median())))
    r = torch.arange(m.shape[0])[:, None].expand_as(m)
    lowest = torch.where(m, r, -1).amax(0)
    low = m & (r > lowest[None] - band * (int(rows[-1]) - int(rows[0]) + 1))
    near = (torch.cdist(lab[low], torch.stack(centres)) < torch.tensor(tols)[None]).any(1)
    road = torch.zeros_like(m)
    road[low] = near
    edge = torch.zeros_like(m)  # a pixel with a 4-neighbour outside the mask
    edge[1:] |= ~m[:-1]
    edge[:-1] |= ~m[1:]
    edge[:, 1:] |= ~m[:, :-1]
    edge[:, :-1] |= ~m[:, 1:]
    _, label = cv2.connectedComponents(road.numpy().astype(np.uint8), connectivity=4)
    label = torch.from_numpy(label)
    touching = label[road & edge].unique()
    out[y0:y1, x0:x1] = road & torch.isin(label, touching[touching > 0])
    return out


#: :func:`registered_tyres`: a wheel's rim diameter as a share of its tyre's (car wheels: 15-18 inch rims in 22-26
#: inch tyres, 0.6-0.7): the tyre is the rim's ellipse grown by its inverse.
RIM_SHARE = 0.65
#: :func:`registered_tyres`: a rim pixel's largest CIE76 chroma (a*b* length; alloy and steel are grey).
RIM_CHROMA = 15.0
#: :func:`registered_tyres`: template tyres seen on fewer pixels are left where they are (too small to place).
TYRE_MIN_PX = 30
#: :func:`registered_tyres`: a rim's box is at least this share of its template tyre's height tall, and at least this
#: share of its own width (a wheel's face seen from any side of the car is an upright ellipse; a grey bumper strip or
#: diffuser is wide and flat).
RIM_MIN_HEIGHT = 0.3
#: :func:`registered_tyres`: a rim's box is at least this share of its height wide (a lit edge of a wheel arch or a
#: door is a thin line; a wheel seen so nearly edge-on shows little rim).
RIM_MIN_WIDTH = 0.25
#: :func:`registered_tyres`: a rim blob has at least this share of its template tyre's visible pixels, and fills at
#: least :data:`RIM_MIN_FILL` of its box's ellipse (a rain streak or a reflection across a dark car is thin and
#: slanted; a rim is a solid disc of metal and spokes, closed over their gaps).
RIM_MIN_AREA = 0.2
RIM_MIN_FILL = 0.4
#: :func:`registered_tyres`: a rim's box is at most this share of its template tyre's visible height tall (the arch
#: may hide the template tyre's top half; a lit grey panel of a dark car is larger).
RIM_MAX_HEIGHT = 1.5


def registered_tyres(lab: Tensor, car: Tensor, tyres: Tensor,
                     paint_light: float) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """``(tyres (H, W) bool, freed (H, W) bool, wheel_at (H, W, 2) float64, wheels (N, 4) float64)``: a dark car's
    tyres and rims where the picture shows them, from its fitted template's tyre pixels ``tyres (H, W)`` (part
    :data:`~sdn3d.meshes.parts.Part.TYRE`) and the picture's ``lab (H, W, 3)`` CIE Lab on the car's pixels
    ``car (H, W)``; ``freed``: the template's tyre pixels that no tyre took (the car's paint, where the template's
    wheel was misplaced); ``wheel_at``: for each pixel of a template tyre that took a tyre, the ``(x, y)`` pixel
    coordinates of the same point of the real wheel (the template tyre's box mapped onto the real tyre's ellipse's
    box), NaN elsewhere: a turned car's wheel drawn from the photo reads the real wheel, rim and rubber, there;
    ``wheels``: each real tyre's ellipse ``(x, y, semi-axis x, semi-axis y)`` in pixels.

    A template's wheel sits where its loft puts it, not where the photographed car's wheel is: on the real frame in
    ``tests/data`` the black car's rear tyre lay a third of a wheel behind the template's, under its body part, and a
    recolour painted it blue. Black rubber is as dark as black paint, but the rim inside it is light grey metal: rim
    pixels are the car's grey pixels (chroma under :data:`RIM_CHROMA`) more than :data:`DARK_PAINT_LIFT` lighter
    than ``paint_light`` (the paint's median L*), closed over a spoke's gap. Each template tyre (a connected part of
    ``tyres`` of at least :data:`TYRE_MIN_PX` pixels, of height ``h``) takes the rim blob nearest its centre within
    ``h`` sideways and ``h / 2`` up or down that is upright (taller than wide, at least :data:`RIM_MIN_WIDTH` of its
    height wide, between :data:`RIM_MIN_HEIGHT` and :data:`RIM_MAX_HEIGHT` of ``h`` tall), solid enough
    (:data:`RIM_MIN_AREA`, :data:`RIM_MIN_FILL`) and whose tyre (the
    ellipse of the blob's box grown by ``1 /`` :data:`RIM_SHARE` about its centre, on the car) is rubber around it
    (its pixels off the blob at most half :data:`DARK_PAINT_LIFT` lighter than the paint, median: a lit grey panel
    of a dark grey car is no rim). A template tyre without such a blob stays where the template put it (freeing
    nothing)."""
    import cv2

    out = torch.zeros_like(tyres)
    freed = torch.zeros_like(tyres)
    height, width = tyres.shape
    wheel_at = torch.full((height, width, 2), math.nan, dtype=torch.float64)
    wheels: list[tuple[float, float, float, float]] = []
    rim = (car & (lab[..., 0] > paint_light + DARK_PAINT_LIFT) & (lab[..., 1:].norm(dim=-1) < RIM_CHROMA))
    closed = cv2.morphologyEx(rim.numpy().astype(np.uint8), cv2.MORPH_CLOSE,
                              cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5)))
    _, _, blobs, _ = cv2.connectedComponentsWithStats(closed, connectivity=8)
    count, labels, stats, tyre_centres = cv2.connectedComponentsWithStats(tyres.numpy().astype(np.uint8),
                                                                          connectivity=8)
    labels = torch.from_numpy(labels)
    yy, xx = torch.meshgrid(torch.arange(height, dtype=torch.float64), torch.arange(width, dtype=torch.float64),
                            indexing="ij")
    for k in range(1, count):
        comp = labels == k
        h, area = int(stats[k][3]), int(stats[k][4])
        if area < TYRE_MIN_PX:
            out |= comp
            continue
        cx, cy = (float(v) for v in tyre_centres[k])
        best, best_d, best_box = None, math.inf, None
        for j in range(1, len(blobs)):
            bx, by, bw, bh, blob_area = (int(v) for v in blobs[j])
            jx, jy = bx + (bw - 1) / 2, by + (bh - 1) / 2
            if (not RIM_MIN_HEIGHT * h <= bh <= RIM_MAX_HEIGHT * h or not RIM_MIN_WIDTH * bh <= bw <= bh
                    or abs(jx - cx) > h or abs(jy - cy) > h / 2 or blob_area < RIM_MIN_AREA * area
                    or blob_area < RIM_MIN_FILL * math.pi / 4 * bw * bh):
                continue
            ax, ay = (bw + 1) / 2 / RIM_SHARE, (bh + 1) / 2 / RIM_SHARE
            tyre = (((xx - jx) / ax) ** 2 + ((yy - jy) / ay) ** 2 <= 1.0) & car
            rubber = tyre & ~torch.from_numpy(closed > 0)
            if not bool(rubber.any()) or float(lab[..., 0][rubber].median()) > paint_light + DARK_PAINT_LIFT / 2:
                continue  # a lit panel, not a rim in a dark tyre
            d = math.hypot(jx - cx, jy - cy)
            if d < best_d:
                best, best_d, best_box = tyre, d, (jx, jy, ax, ay)
        if best is None:
            out |= comp
            continue
        out |= best
        freed |= comp & ~best
        tx, ty, tw = int(stats[k][0]), int(stats[k][1]), int(stats[k][2])
        jx, jy, ax, ay = best_box
        wheels.append(best_box)
        # box centre to box centre, half-sizes to semi-axes (the template's visible tyre is one wheel face)
        wheel_at[comp] = torch.stack([jx + (xx[comp] - (tx + (tw - 1) / 2)) * ax / (tw / 2),
                                      jy + (yy[comp] - (ty + (h - 1) / 2)) * ay / (h / 2)], 1)
    return out, freed & ~out, wheel_at, torch.tensor(wheels, dtype=torch.float64).view(-1, 4)


def recolor_pixels(colors: Tensor, target_rgb: tuple[float, float, float],
                   body_part: bool = False, reference: Tensor | None = None) -> tuple[Tensor, Tensor, dict]:
    """Repaint a car's body (module doc, step 5).

    With ``body_part`` the pixels are the fitted mesh's body part (:func:`body_paint` picks the paint among them)
    and the paint takes the target's hue outright, each pixel keeping its chroma relative to the paint's and its
    lightness offset: a pixel's hue never mixes the old and the new paint (an additive Lab shift of a red car to
    blue turned its orange highlights and dark shades magenta). A dark grey or black paint keeps the pixels at most
    :data:`DARK_PAINT_LIFT` lighter than its median (rims, trim, road and reflections are not repainted).

    Args:
        colors: ``(P, 3)`` sRGB in [0, 1], the car's pixels; target_rgb: the paint, sRGB in [0, 1].
        body_part: ``colors`` are the body part's pixels only (see above); False: all the car's pixels, the paint
            found as the largest colour cluster (:func:`_paint`) and moved by one Lab shift.
        reference: ``(R, 3)`` sRGB, with ``body_part``: the body part's pixels, when ``colors`` are more of the car's
            (:func:`body_paint`'s ``reference``: they set the paint).

    Returns:
        ``(new colours (P, 3), body (P,) bool, stats)``; ``stats``: ``body_share``, ``delta_e`` (CIE76 distance of
        the repainted body's mean Lab to the target's).

    Example:
        >>> import torch
        >>> car = torch.tensor([[0.8, 0.8, 0.82]]).repeat(300, 1) * torch.linspace(0.7, 1.0, 300)[:, None]
        >>> car[:60] = 0.05  # windows and tyres
        >>> new, body, stats = recolor_pixels(car, (0.7, 0.08, 0.08))
        >>> bool(body[:60].any()), bool(body[60:].all()), stats["delta_e"] < 3, bool((new[:60] == car[:60]).all())
        (False, True, True, True)
    """
    if len(colors) < 8:
        return colors, torch.zeros(len(colors), dtype=torch.bool), {"body_share": 0.0, "delta_e": float("nan")}
    lab = srgb_to_lab(colors)
    target = srgb_to_lab(torch.tensor([target_rgb], dtype=colors.dtype))[0]
    if body_part:
        body, coloured = body_paint(lab, reference=None if reference is None else srgb_to_lab(reference))
        if not coloured and bool(body.any()):  # a dark paint: much lighter grey pixels are not it
            paint_light = lab[body, 0].median()
            if float(paint_light) < DARK_PAINT_L:
                body &= lab[:, 0] < paint_light + DARK_PAINT_LIFT
        if not bool(body.any()):
            return colors, body, {"body_share": 0.0, "delta_e": float("nan")}
        paint = lab[body]
        new_lab = lab.clone()
        new_lab[:, 0] = lab[:, 0] + (target[0] - paint[:, 0].median())
        if coloured:  # chroma relative to the paint's, the target's hue
            rel = (lab[:, 1:].norm(dim=1) / paint[:, 1:].norm(dim=1).median().clamp(min=1e-6)).clamp(0.3, 1.6)
            new_lab[:, 1:] = target[1:][None] * rel[:, None]
        else:  # grey paint: the target's chroma plus each pixel's small tint
            new_lab[:, 1:] = target[1:][None] + (lab[:, 1:] - paint[:, 1:].mean(0))
    else:
        body = _paint(lab)
        new_lab = lab + (target - lab[body].mean(0))
    new = _rgb(new_lab).clamp(0, 1)
    out = torch.where(body[:, None], new, colors)
    delta = float((srgb_to_lab(out[body]).mean(0) - target).norm())
    return out, body, {"body_share": float(body.double().mean()), "delta_e": delta}


#: D65 linear RGB -> XYZ and back, and the D65 white, as kornia 0.9's ``rgb_to_lab`` / ``lab_to_rgb`` use them.
_RGB_TO_XYZ = ((0.412453, 0.357580, 0.180423), (0.212671, 0.715160, 0.072169), (0.019334, 0.119193, 0.950227))
_XYZ_TO_RGB = ((3.2404813432005266, -1.5371515162713185, -0.4985363261688878),
               (-0.9692549499965682, 1.8759900014898907, 0.0415559265582928),
               (0.0556466391351772, -0.2040413383665112, 1.0573110696453443))
_WHITE = (0.95047, 1.0, 1.08883)


def srgb_to_lab(rgb: Tensor) -> Tensor:
    """``(P, 3)`` CIE Lab (D65, 2 degrees) of sRGB rows in [0, 1]: kornia 0.9's ``rgb_to_lab`` op for op, so the values
    are bit-identical to it (a test checks) without importing kornia (about 0.4 s of an edit command's start-up).

    >>> [round(v, 2) for v in srgb_to_lab(torch.tensor([[1.0, 0.0, 0.0]]))[0].tolist()]
    [53.24, 80.09, 67.2]
    """
    image = rgb.float().clamp(0, 1).T[:, :, None]  # (3, P, 1), kornia's layout
    # kornia's operations, each on a temporary of its own where kornia made a new one (the same layout, so the same
    # elements take torch's vectorised and its scalar paths as in kornia: the values depend on it)
    lin = torch.where(image > 0.04045, (image + 0.055).clamp_(min=0.0).div_(1.055).pow_(2.4), image / 12.92)
    xyz = torch.einsum("oi, ...ihw -> ...ohw", torch.tensor(_RGB_TO_XYZ, dtype=lin.dtype), lin)
    xyz = xyz.div_(torch.tensor(_WHITE, dtype=xyz.dtype)[..., :, None, None])
    threshold = 0.008856
    f = torch.where(xyz > threshold, xyz.clamp(min=threshold).pow_(1 / 3.0), (7.787 * xyz).add_(4.0 / 29.0))
    x, y, z = f[..., 0, :, :], f[..., 1, :, :], f[..., 2, :, :]
    lab = torch.stack([(116.0 * y).sub_(16.0), (x - y).mul_(500.0), (y - z).mul_(200.0)], dim=-3)
    return lab[:, :, 0].T


def _rgb(lab: Tensor) -> Tensor:
    """``(P, 3)`` sRGB in [0, 1] of CIE Lab rows: kornia 0.9's ``lab_to_rgb(clip=True)`` op for op (bit-identical)."""
    image = lab.float().T[:, :, None]  # (3, P, 1)
    fy = (image[..., 0, :, :] + 16.0) / 116.0
    fx = (image[..., 1, :, :] / 500.0) + fy
    fz = (fy - (image[..., 2, :, :] / 200.0)).clamp(min=0.0)
    fxyz = torch.stack([fx, fy, fz], dim=-3)
    xyz = torch.where(fxyz > 0.2068966, torch.pow(fxyz, 3.0), (fxyz - 4.0 / 29.0) / 7.787)
    xyz = xyz * torch.tensor(_WHITE, dtype=xyz.dtype)[..., :, None, None]
    lin = torch.einsum("oi, ...ihw -> ...ohw", torch.tensor(_XYZ_TO_RGB, dtype=xyz.dtype), xyz)
    threshold = 0.0031308
    rgb = torch.where(lin > threshold, 1.055 * torch.pow(lin.clamp(min=threshold), 1 / 2.4) - 0.055, 12.92 * lin)
    return torch.clamp(rgb, min=0.0, max=1.0)[:, :, 0].T
