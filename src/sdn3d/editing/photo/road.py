"""Filling a vacated region along the road's perspective lines (the photo appearance's ``fill='rays'``; step 2 of
:mod:`sdn3d.editing.photo`).

In a driving scene most of what a removed car hid runs along the road: lane markings, kerbs, verges, guard rails,
the feet of facades. In a pinhole picture such lines all meet at the road's vanishing point, so each of them is a
ray from that point. :func:`ray_fill` fills each hole pixel from the nearest pixels outside the hole on its own ray,
one towards the vanishing point (farther along the road) and one away from it (nearer), interpolated by distance: a
lane line that enters the hole leaves it where it should, and the road stays road (the rectified bird's-eye fill of
issue 41 in one step: a column of the bird's-eye view is a ray in the picture). :func:`vanishing_point` is that point
for a direction on the road plane (a car's long axis), or the camera's forward one.

Sources are the pixels that are neither in the hole nor in ``keep_out`` (other objects); the values sampled are a
normalised blur of the sources (no single noisy pixel sets a whole ray), and the road's fine texture is put back by
adding the high-pass of the sources mirrored across the hole's edge along the same ray (``texture``: its weight), so
that the fill is not smoother than the road around it. A pixel no ray reaches (the vanishing point's own
neighbourhood, a hole at the picture's edge with nothing beyond) is left to Telea.
"""

from __future__ import annotations

import ctypes
import functools
import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.editing.photo.settings import VANISHING_MODES, VERGE_MODES
from sdn3d.image_ops import (
    any_along,
    any_set,
    count_set,
    dilate_cross,
    dilate_square,
    luminance,
    nonzero_yx,
    padded_window,
)
from sdn3d.math3d.sums import sum3
from sdn3d.native import load_kernel
from sdn3d.road_heading import road_near

__all__ = ["vanishing_point", "removal_vanishing_point", "ray_fill", "shadowed_road",
           "road_shade", "road_haze", "RAY_CHUNK", "GRAIN_SIGMA", "GRAIN_FOLD", "GRAIN_EDGE",
           "GRAIN_WEIGHTS",
           "road_colours", "road_like", "ab_length", "verge_like", "VERGE_CHROMA", "VERGE_MIN_LIGHT", "FAR_RESOLVED",
           "NEAR_REACH"]

#: Gaussian sigma (pixels) below which a source's detail is the road's grain (:func:`ray_fill`'s ``texture``).
GRAIN_SIGMA = 1.0
#: A source pixel's high-pass beyond this many robust standard deviations of the picture's (its luma's median absolute
#: value, scaled) is an edge, not grain (:func:`ray_fill`).
GRAIN_EDGE = 4.0
#: Depth (pixels) into the hole beyond which the mirrored grain folds back towards the hole's edge.
GRAIN_FOLD = 24.0
#: Hole pixels traced at once (memory: ``RAY_CHUNK x steps`` samples per side).
RAY_CHUNK = 8192


def vanishing_point(K: Tensor, ry: float | None = None, min_forward: float = 0.5) -> tuple[float, float]:
    """``(u, v)`` pixel where lines of the road plane along a car of yaw ``ry`` (KITTI convention: its long axis is
    ``(cos ry, 0, -sin ry)`` in the camera frame) meet; the camera's forward direction ``(0, 0, 1)`` when ``ry`` is
    None or the car is turned across the road (its axis' forward component under ``min_forward``), since a car
    crossing the picture says nothing about where the road runs."""
    d = torch.tensor([0.0, 0.0, 1.0], dtype=torch.float64)
    if ry is not None:
        axis = torch.tensor([math.cos(ry), 0.0, -math.sin(ry)], dtype=torch.float64)
        axis = axis if float(axis[2]) >= 0 else -axis
        if float(axis[2]) >= min_forward:
            d = axis
    p = K.double() @ d
    return float(p[0] / p[2]), float(p[1] / p[2])


def removal_vanishing_point(image: Tensor, K: Tensor, removed: Tensor, objects_px: Tensor,
                            ry: float | None = None) -> tuple[float, float]:
    """``(u, v)`` the road's vanishing point for filling ``removed (H, W)`` (the pixels of the objects that left):
    :func:`~sdn3d.road_heading.road_near`, the edges around them (within twice their extent, on no object of
    ``objects_px (H, W)``), else :func:`vanishing_point` of the first removed car's yaw ``ry`` (a fitted pose can
    be mirrored; the road's own lines cannot), else the camera's forward one."""
    found = road_near(image, K, removed, objects_px)
    return found if found is not None else vanishing_point(K, ry)


def _masked_blur(image: Tensor, valid: Tensor, sigma: float, sigma_y: float | None = None) -> tuple[Tensor, Tensor]:
    """``((C, H, W), (H, W))``: the Gaussian blur (sigma ``sigma`` along rows, ``sigma_y`` across them; None: the
    same) of ``image (C, H, W)`` over ``valid (H, W)`` pixels only, divided by the blurred weight (each pixel's local
    mean of valid pixels; invalid ones are never read), and that blurred weight (the share of valid pixels around)."""
    import cv2

    sy = sigma if sigma_y is None else sigma_y
    w = valid.float().numpy()
    channels = image.float().numpy()
    # each channel's product and blur into one buffer, the quotient in place: the same values as a stack of the
    # channels' blurs divided into a new array, without a whole picture's temporaries (fresh memory at 1242x375)
    num = np.empty(channels.shape, np.float32)
    weighted = np.empty(channels.shape[1:], np.float32)
    for c, blurred in zip(channels, num, strict=True):
        np.multiply(c, w, out=weighted)
        blurred[...] = cv2.GaussianBlur(weighted, (0, 0), sigma, sigmaY=sy)
    den = cv2.GaussianBlur(w, (0, 0), sigma, sigmaY=sy)
    np.divide(num, np.maximum(den, 1e-6)[None], out=num)
    return torch.from_numpy(num).to(image.dtype), torch.from_numpy(den)


def _blur_reach(sigma: float) -> int:
    """Pixels at least as far as :func:`_masked_blur`'s kernel reaches at ``sigma``: OpenCV sizes a float picture's
    Gaussian ``round(8 sigma + 1) | 1`` taps, a reach of at most ``4 sigma + 1.25``."""
    return math.ceil(4 * sigma) + 1


def _normalised_blur(image: Tensor, valid: Tensor, sigma: float) -> Tensor:
    """``(3, H, W)``: the Gaussian blur of ``image`` over ``valid`` pixels only, divided by the blurred weight
    (:func:`_masked_blur`; ``sigma`` <= 0: ``image`` as it is)."""
    if sigma <= 0:
        return image
    return _masked_blur(image, valid, sigma)[0]


#: :func:`_coarse_blur`'s downsampling factor.
COARSE = 4


def _coarse_blur(image: Tensor, valid: Tensor, sigma: float, road: Tensor | None = None) -> Tensor:
    """``(3, H / COARSE, W / COARSE)``: :func:`_normalised_blur` of ``image`` over ``valid`` at sigma ``sigma``
    (input pixels), computed on the picture shrunk :data:`COARSE` times (a wide blur at full size costs tens of ms
    at 1242x375); read it with :func:`_gather_coarse`. ``road (3,)`` (CIE Lab): over the valid cells that are road
    alone (mostly valid, and not :func:`verge_like` by their mean valid colour: judged on the shrunk picture's cells,
    the cost of a sixteenth of the pixels), the road's colour around a point without its markings' detail, which
    :func:`ray_fill` with ``verge='road'`` carries from a ray's far side alone (a marking seen on one side only is not
    drawn out into a stripe, as in :func:`_one_sided_marks`)."""
    import cv2

    height, width = valid.shape
    size = (max(width // COARSE, 1), max(height // COARSE, 1))
    w = valid.float().numpy()
    small_w = cv2.resize(w, size, interpolation=cv2.INTER_AREA)
    weighted = np.empty(w.shape, np.float32)  # each channel's product in one buffer (the same values as c * w)
    small = [cv2.resize(np.multiply(c, w, out=weighted), size, interpolation=cv2.INTER_AREA)
             for c in image.float().numpy()]
    if road is not None:
        cells = torch.from_numpy(np.stack(small) / np.maximum(small_w, 1e-6)[None]).view(3, -1)  # mean valid colours
        kind = ((small_w > 0.5) & ~verge_like(cells, road).view(small_w.shape).numpy()).astype(np.float32)
        small_w, small = small_w * kind, [c * kind for c in small]
    den = cv2.GaussianBlur(small_w, (0, 0), sigma / COARSE)
    num = np.stack([cv2.GaussianBlur(c, (0, 0), sigma / COARSE) for c in small])
    return torch.from_numpy(num / np.maximum(den, 1e-6)[None]).to(image.dtype)


def _gather_coarse(small: Tensor, points: Tensor) -> Tensor:
    """``(3, N)`` :func:`_gather` of a :func:`_coarse_blur` picture at full-size ``points (N, 2)`` (x, y)."""
    return _gather(small, (points + 0.5) / COARSE - 0.5)


RAY_SOURCE = Path(__file__).with_name("ray_kernel.cpp")
RAY_ABI_VERSION = 2


def _bind_ray(lib: ctypes.CDLL) -> ctypes.CDLL:
    ptr, i64 = ctypes.c_void_p, ctypes.c_int64
    lib.sdn3d_ray_trace_f32.argtypes = [ptr, ptr, ptr, i64, i64, ptr, i64, ptr, i64, ptr, ptr]
    lib.sdn3d_ray_trace_f32.restype = None
    lib.sdn3d_ray_along_f32.argtypes = [ptr, ptr, ptr, i64, i64, i64, i64, ptr, ptr]
    lib.sdn3d_ray_along_f32.restype = None
    return lib


@functools.lru_cache(maxsize=1)
def ray_kernel() -> ctypes.CDLL | None:
    """The loaded ray kernel (``ray_kernel.cpp``: :func:`_trace` ray by ray and :func:`_along`'s points), or
    ``None`` when it cannot be built (then their PyTorch paths run, the same answers)."""
    return load_kernel(RAY_SOURCE, "sdn3d_ray_abi_version", RAY_ABI_VERSION, _bind_ray, "the photo's ray fill")


def _trace(pix: Tensor, unit: Tensor, valid: Tensor, steps: Tensor, limit: Tensor | None) -> tuple[Tensor, Tensor]:
    """``(distance (N,), found (N,))``: the first step of ``steps (S,)`` (pixels, increasing) at which the point
    ``pix + step * unit`` is a ``valid (H, W)`` pixel, for each ``pix (N, 2)`` (x, y) inside the picture and unit
    vector ``unit (N, 2)``; a step beyond ``limit (N,)`` (None: no limit) or outside the picture does not count
    (distance ``steps[0]`` where none does).

    The C++ kernel (:func:`ray_kernel`) walks each ray's steps one by one up to its first hit, with the same float32
    product, sum and rounding as the PyTorch path (:func:`_trace_blocks_torch`): the same answer bit for bit, in
    about a third of its time on the real frame's removals at 1242x375 (that path's ``(rays, block)`` temporaries
    and blocks looked at past a ray's hit; docs/results/2026-12-03_cpu/session39/rays/)."""
    f32 = all(t.dtype == torch.float32 for t in (pix, unit, steps, *(() if limit is None else (limit,))))
    kernel = ray_kernel() if f32 and valid.dtype == torch.bool and len(steps) and len(pix) else None
    if kernel is None:
        return _trace_blocks_torch(pix, unit, valid, steps, limit)
    pix, unit, steps = pix.contiguous(), unit.contiguous(), steps.contiguous()
    mask = valid.contiguous().view(torch.uint8)
    lim = None if limit is None else limit.contiguous()
    distance = torch.empty(len(pix), dtype=torch.float32)
    found = torch.empty(len(pix), dtype=torch.bool)
    kernel.sdn3d_ray_trace_f32(pix.data_ptr(), unit.data_ptr(), mask.data_ptr(), valid.shape[0], valid.shape[1],
                               steps.data_ptr(), len(steps), None if lim is None else lim.data_ptr(), len(pix),
                               distance.data_ptr(), found.data_ptr())
    return distance, found


def _trace_blocks_torch(pix: Tensor, unit: Tensor, valid: Tensor, steps: Tensor,
                        limit: Tensor | None) -> tuple[Tensor, Tensor]:
    """:func:`_trace`'s PyTorch path (no C++ compiler).

    The steps are looked at in blocks (:data:`TRACE_BLOCKS`), each for the rays not found yet and not past their
    limit: most rays leave the hole within a few steps, so the work follows the hole's depth, not ``S``. Points are
    rounded to pixels as one ``(N, S)`` pass would, and looked up in ``valid`` padded by ``steps[-1] + 1`` pixels of
    False (the outside counts as not valid), so the result is the same."""
    height, width = valid.shape
    margin = int(math.ceil(float(steps[-1]))) + 1 if len(steps) else 1
    # looked up by NumPy's take: a third of the cost of torch's indexing of a (A, B) block (the same booleans)
    padded = F.pad(valid, (margin, margin, margin, margin)).reshape(-1).numpy()
    row = float(width + 2 * margin)
    exact = padded.size < 2**24
    distance = steps[:1].expand(len(pix)).clone()
    found = torch.zeros(len(pix), dtype=torch.bool)
    active = torch.arange(len(pix))
    px, py, ux, uy = pix[:, :1], pix[:, 1:], unit[:, :1], unit[:, 1:]
    start = 0
    for block in _trace_blocks(len(steps)):
        st = steps[start:start + block]
        start += block
        if limit is not None:
            active = active[limit[active] >= st[0]]  # steps increase: a ray past its limit finds nothing more
        if not len(active):
            break
        # (A, B): as (p + st * u).round() per coordinate (a product, then a sum: no fused multiply-add), in place
        x = (st * ux[active]).add_(px[active]).round_()
        y = (st * uy[active]).add_(py[active]).round_()
        if exact:  # integers below 2^24: the index is exact in float, whatever the order of its sums
            index = y.mul_(row).add_(x).add_(margin * row + margin).long()
        else:
            index = (y.long() + margin) * int(row) + (x.long() + margin)
        ok = padded.take(index.numpy())
        if limit is not None:
            ok &= (st[None] <= limit[active, None]).numpy()
        hit = ok.any(1)
        if hit.any():
            first = torch.from_numpy(ok[hit].argmax(1))  # the first True
            hit = torch.from_numpy(hit)
            distance[active[hit]] = st[first]
            found[active[hit]] = True
            active = active[~hit]
    return distance, found


def _hole_to_vanishing(pix: Tensor, unit: Tensor, reach: Tensor, found_in: Tensor, hole: Tensor,
                       steps: Tensor) -> Tensor:
    """``(N,)`` bool: the points ``pix (N, 2)`` whose ray towards the vanishing point (``-unit (N, 2)``, ``reach
    (N,)`` pixels to it; ``found_in (N,)``: a source was found on it) stays inside ``hole (H, W)`` all the way there,
    within the traced ``steps``: the hole covers the vanishing point, and what lies on the ray's far side, the road's
    far end and the horizon, is hidden. A ray stopped by another object or by the picture's edge is not one of them
    (its near side is still the same road line).

    Why these are not filled from their near side alone: near the vanishing point the road's colour changes fastest
    with the row (its depth: fog, haze, the far road's light), and above it lies no road at all, so a near-side
    colour carried along the ray draws the near road's colour up to the horizon and the near background's down to
    it (the dark cross of the tuning deletes of a far car straight ahead)."""
    limit = (reach - 1.0).clamp(min=0)
    out = ~found_in & (limit <= float(steps[-1]))
    if any_set(out):
        _, left = _trace(pix[out], -unit[out], ~hole, steps, limit[out])
        out[out.clone()] = ~left
    return out


#: ``ray_fill(vanishing='telea')``: a ray whose far side the hole hides (:func:`_hole_to_vanishing`) is still drawn
#: from its near side alone at the pixels at most this many times as deep as that side (on the road plane depth goes as
#: one over the distance to the vanishing point along the ray): the road just beyond the hole's near edge changes
#: little, the road near the horizon most.
NEAR_REACH = 2.0


#: :func:`_trace`'s block sizes: small first (most rays leave the hole within a few pixels), then doubling.
TRACE_BLOCKS = (8, 8, 16, 32, 64)


def _trace_blocks(total: int) -> list[int]:
    """Block sizes covering ``total`` steps: :data:`TRACE_BLOCKS`, then blocks as large as the last."""
    out, done = [], 0
    for b in (*TRACE_BLOCKS, *([TRACE_BLOCKS[-1]] * (total // TRACE_BLOCKS[-1] + 1))):
        if done >= total:
            break
        out.append(min(b, total - done))
        done += out[-1]
    return out


def ray_fill(image: Tensor, hole: Tensor, vp: tuple[float, float], keep_out: Tensor | None = None,
             sigma: float = 1.0, texture: float = 1.0, along: int = 1, max_steps: int = 400,
             beyond: int = 64, match_grain: bool = False, marks: float = 0.0,
             haze: float = 0.0, airlight: float = 0.25, road: Tensor | None = None,
             verge: str = "blend", ground_row: float = 0.0, lab: PictureLab | None = None,
             vanishing: str = "near") -> tuple[Tensor, Tensor]:
    """``(image (3, H, W), reached (H, W) bool)``: ``image`` with the ``hole (H, W)`` pixels a ray reaches filled
    along the rays from the vanishing point ``vp = (u, v)`` (module doc); ``keep_out (H, W)``: pixels no ray samples
    (other objects), ``sigma``: the sources' normalised blur, ``texture``: weight of the mirrored high-pass,
    ``along``: source pixels averaged along the ray from its first one outward (a lane line runs along the ray, so
    this smooths noise without blurring it), ``max_steps``: how far (pixels) a ray looks on each side at most,
    ``beyond``: and at most this far past the hole's box diagonal (through other objects and shadows);
    ``match_grain``: instead of ``texture``, the weight of :data:`GRAIN_WEIGHTS` whose fill's road is as
    fine-textured as the road around the hole (:func:`_matched_weight`): a photo's asphalt has more grain
    than a render's; ``marks``: where one side of a ray is a marking (near grey and more than ``marks`` lighter in
    luma than its neighbourhood) and the other is not, the ray takes the other side's colour alone
    (:func:`_one_sided_marks`; 0: both sides interpolated everywhere); ``haze``: weight of the change of the road's
    colour with its row (:func:`road_haze`: fog and haze lighten the road towards the horizon) added to each hole
    pixel, from its sources' rows to its own (0: the sources' colours as they are); ``airlight``: only where the
    fitted fog's colour is within this of the far picture's (:func:`road_haze`'s fog check; 1: no check);
    ``road (3,)``: the road's CIE Lab around the hole (:func:`road_colours`) and ``verge``
    (:data:`~sdn3d.editing.photo.settings.VERGE_MODES`): ``'blend'`` interpolates a ray's two sides whatever they
    are; ``'road'``: a ray whose near side is a verge (grass, foliage, paint, a hedge: :func:`verge_like`) and whose
    far side is road (:func:`_verge_sides`) takes the road's colour there alone, without its markings' detail
    (:func:`_coarse_blur` of the road), so no pale band of the verge's colour fades across the road where the car
    stood and no marking of the far side is drawn across it (None ``road``: ``'blend'``), at the hole pixels from row
    ``ground_row`` down (the ground near the removed car; higher up a ray's sides may be upright things) whose far
    side is resolved (:data:`FAR_RESOLVED`); so do the rays that meet a verge on both sides among a run of rays whose
    near-side verge mostly ended inside the hole (:func:`_ended_verge_runs`); ``'edges'``: as ``'road'``, but those
    rays' pixels inside the verge's edges continued straight into the hole (:func:`_continued_verge`) take the verge
    mirrored across the hole's edge along the ray, with its own grain. ``lab``: ``image``'s
    :class:`PictureLab` (the road tests' Lab, converted once for all the removal's tests). ``vanishing``
    (:data:`~sdn3d.editing.photo.settings.VANISHING_MODES`): a pixel whose ray runs inside the hole all the way to the
    vanishing point (:func:`_hole_to_vanishing`: the hole covers that point, a car straight ahead) has no far side;
    ``'near'`` fills it from its near side alone, ``'telea'`` only where it is at most :data:`NEAR_REACH` times as
    deep as its near side and leaves the rest unreached (Telea fills it from the pixels around, the rays' ones
    included)."""
    if vanishing not in VANISHING_MODES:
        raise ValueError(f"ray_fill: vanishing must be one of {VANISHING_MODES}, got {vanishing!r}")
    if verge not in VERGE_MODES:
        raise ValueError(f"ray_fill: verge must be one of {VERGE_MODES}, got {verge!r}")
    if lab is not None:
        lab.check(image)
    height, width = hole.shape
    out = image.clone()
    reached = torch.zeros_like(hole)
    if not any_set(hole):
        return out, reached
    valid = ~hole if keep_out is None else ~hole & ~keep_out
    if not any_set(valid):
        return out, reached
    smooth = _normalised_blur(image, valid, sigma)
    broad = _coarse_blur(image, valid, MARK_SIGMA) if marks > 0 else None
    # The sources' grain: their high-pass at one pixel's scale (0 elsewhere: never a car's edge).
    detail = grain_kept = None
    if texture > 0 or match_grain:
        blur = _normalised_blur(image, valid, GRAIN_SIGMA)
        # in place in the blur's own fresh tensor: the same difference and product as (image - blur) * valid
        detail = (torch.sub(image, blur, out=blur) if blur is not image and blur.dtype == image.dtype
                  else image - blur).mul_(valid)
        # A marking's or a kerb's outline is no grain: mirrored into the hole it draws a ghost outline there.
        # the channels' mean as torch's mean computes it (their sum, then / 3), without its reduction's scalar loop
        # over the three adjacent values of a channel-last picture (a third of the time)
        level = (sum3(detail, 0) / 3).abs()
        scale = 1.4826 * _masked_median(level, valid) if any_set(valid) else 0.0
        # applied where the grain is read (_mirrored: the same product at each pixel read), not to the whole picture
        grain_kept = level <= GRAIN_EDGE * scale
    ys, xs = nonzero_yx(hole)
    pix = torch.stack([xs, ys], 1).float()
    centre = torch.tensor(vp, dtype=torch.float32)
    away = pix - centre
    reach = away.norm(dim=1)  # distance to the vanishing point
    unit = torch.where(reach[:, None] > 1.0, away / reach.clamp(min=1e-6)[:, None], torch.tensor([1.0, 0.0]))
    # No ray needs to look farther than across the hole's box and ``beyond`` past it (the cost: samples per ray).
    across = math.hypot(float(ys.max() - ys.min()), float(xs.max() - xs.min()))
    # Every pixel near a pixel's own place, every other one farther on (half the samples; a source is a few
    # pixels wide).
    far = min(max_steps, int(across) + beyond)
    steps = torch.cat([torch.arange(1, 17), torch.arange(17, far + 1, 2)]).float()
    never = None if float(steps[-1]) <= far else torch.full_like(reach, float(far))  # None: every step is within
    per_row = road_haze(image, valid, hole, float(vp[1]), airlight, lab) if haze > 0 else None
    values = torch.zeros(3, len(ys))
    grains = torch.zeros(3, len(ys)) if detail is not None else None
    got = torch.zeros(len(ys), dtype=torch.bool)
    hidden_far = torch.zeros(len(ys), dtype=torch.bool)  # vanishing='telea': rays whose far side the hole hides
    road_broad = None  # the road's broad colour, for rays taken from their far side alone (verge='road')
    # verge='road': each ray's sides that are a verge (on the ground rows, far side resolved), and the value the ray
    # takes from its far side's road alone, for the rays whose both sides are a verge (:func:`_ended_verge_runs`)
    # and, for the pixels inside the verge continued (:func:`_continued_verge`), its near side's value and place
    near_verge = far_verge = from_road = from_near = near_at = None
    if road is not None and verge in ("road", "edges"):
        near_verge, far_verge = torch.zeros_like(got), torch.zeros_like(got)
        from_road, from_near, near_at = torch.zeros(3, len(ys)), torch.zeros(3, len(ys)), torch.zeros(len(ys), 2)
    for s in range(0, len(ys), RAY_CHUNK):
        p, u, sp = pix[s:s + RAY_CHUNK], unit[s:s + RAY_CHUNK], reach[s:s + RAY_CHUNK]
        # Away from the vanishing point (nearer road) and towards it, stopping there: past it lies another line.
        d_out, f_out = _trace(p, u, valid, steps, None if never is None else never[s:s + RAY_CHUNK])
        d_in, f_in = _trace(p, -u, valid, steps, (sp - 1.0).clamp(min=0))
        q_out, q_in = p + d_out[:, None] * u, p - d_in[:, None] * u
        c_out = _along(smooth, valid, q_out, u, along)
        c_in = _along(smooth, valid, q_in, -u, along)
        w_out = torch.where(f_out, torch.where(f_in, d_in / (d_in + d_out), torch.ones_like(d_in)),
                            torch.zeros_like(d_in))
        w_in = torch.where(f_in, 1 - w_out, torch.zeros_like(d_in))
        if marks > 0:
            w_out, w_in = _one_sided_marks(c_out, c_in, _gather_coarse(broad, q_out), _gather_coarse(broad, q_in),
                                           w_out, w_in, f_out & f_in, marks)
        road_in = None  # the road's broad colour at the far side (verge='road', where a near side is a verge)
        if road is not None and verge in ("road", "edges"):
            # the far side's road is evidence only where it is resolved (FAR_RESOLVED), on the ground rows
            resolved = (sp - d_in) >= FAR_RESOLVED * (sp + d_out)
            near, far = _verge_sides(c_out, c_in, f_out & f_in & resolved & (p[:, 1] >= ground_row), road)
            near_verge[s:s + RAY_CHUNK], far_verge[s:s + RAY_CHUNK] = near, far
            if any_set(near):
                if road_broad is None:
                    road_broad = _coarse_blur(image, valid, MARK_SIGMA, road)
                road_in = _gather_coarse(road_broad, q_in)
                far_only = near & ~far
                w_out, w_in = torch.where(far_only, 0.0, w_out), torch.where(far_only, 1.0, w_in)
                c_in = torch.where(far_only, road_in, c_in)
        val = c_out * w_out + c_in * w_in
        near_in = None  # the ray from its near side's verge alone: the verge mirrored across the hole's edge
        if road_in is not None:
            m = (p + 2 * d_out[:, None] * u).round().long()
            inb = (m[:, 0] >= 0) & (m[:, 0] < width) & (m[:, 1] >= 0) & (m[:, 1] < height)
            mx, my = m[:, 0].clamp(0, width - 1), m[:, 1].clamp(0, height - 1)
            seen = inb & valid[my, mx]
            near_in = torch.where(seen[None], image[:, my, mx].float(), c_out)
        if per_row is not None:  # the road's colour at this pixel's row less its colour at the sources' rows
            def at(rows: Tensor) -> Tensor:
                return per_row[:, rows.round().long().clamp(0, height - 1)]

            at_p, at_in = at(p[:, 1]), at(q_in[:, 1])
            val = val + haze * (at_p - at(q_out[:, 1]) * w_out - at_in * w_in)
            if road_in is not None:  # as a ray from its far side's road alone (w_out 0, w_in 1)
                road_in = road_in + haze * (at_p - at_in)
                near_in = near_in + haze * (at_p - at(q_out[:, 1]))
        if road_in is not None:
            from_road[:, s:s + RAY_CHUNK] = road_in
            from_near[:, s:s + RAY_CHUNK] = near_in
            near_at[s:s + RAY_CHUNK] = q_out
        if detail is not None:  # a side's high-pass, mirrored across the hole's edge along the ray (nearer side first)
            near_out = f_out & (~f_in | (d_out <= d_in))
            grain, ok = _mirrored(detail, valid, torch.where(near_out[:, None], q_out, q_in),
                                  torch.where(near_out[:, None], u, -u), torch.where(near_out, d_out, d_in),
                                  grain_kept)
            other, ok2 = _mirrored(detail, valid, torch.where(near_out[:, None], q_in, q_out),
                                   torch.where(near_out[:, None], -u, u), torch.where(near_out, d_in, d_out),
                                   grain_kept)
            ok2 = ok2 & ~ok & torch.where(near_out, f_in, f_out)
            grains[:, s:s + RAY_CHUNK] = ok * grain + ok2 * other
        values[:, s:s + RAY_CHUNK] = val
        got[s:s + RAY_CHUNK] = f_out | f_in
        if vanishing == "telea":
            # depth on the road plane goes as one over the distance to the vanishing point along the ray
            hidden_far[s:s + RAY_CHUNK] = _hole_to_vanishing(p, u, sp, f_in, hole, steps) & (
                ~f_out | (sp + d_out > NEAR_REACH * sp))
    if vanishing == "telea":
        got &= ~hidden_far
    if near_verge is not None and any_set(near_verge):
        ended = _ended_verge_runs(torch.atan2(unit[:, 1], unit[:, 0]), reach, near_verge, far_verge)
        values[:, ended] = from_road[:, ended]
        # the rays from the road alone (far side road, or an ended verge run) inside the verge's edges continued into
        # the hole take the verge's near side alone up to where they cross its edge
        ends = (near_verge & ~far_verge) | ended
        if verge == "edges" and any_set(ends):
            at = ends.nonzero().flatten()
            kept = at[_continued_verge(image, valid, hole, road, ground_row, pix[at], near_at[at])]
            values[:, kept] = from_near[:, kept]
            if grains is not None:  # the mirrored verge brings its own grain
                grains[:, kept] = 0
    if grains is not None:
        weight = (_matched_weight(image, valid, values[:, got], grains[:, got], ys[got], xs[got], texture, lab)
                  if match_grain and any_set(got) else texture)
        values = values + weight * grains
    out[:, ys[got], xs[got]] = values[:, got].clamp(0, 1).to(out.dtype)
    reached[ys[got], xs[got]] = True
    return out, reached


#: :func:`road_haze`: candidate fog depths, in rows below the horizon (the road at ``r`` rows below it is
#: ``exp(-k / r)`` of the way from the fog's colour to its own).
HAZE_DEPTHS = (2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0)
#: :func:`road_haze`: least road-like pixels on a row for its median to count, and least such rows for a fit.
HAZE_MIN_PIXELS, HAZE_MIN_ROWS = 5, 6
#: :func:`road_haze` reads every ``width // HAZE_COLUMNS``-th column (every one below 800 columns): the profile is
#: per row, and at 1242x375 the road's colour on all columns cost 50 ms.
HAZE_COLUMNS = 400
#: :func:`road_haze`'s fog check: the far picture is the rows within ``height // HAZE_FAR_ROWS`` (at least 2) of the
#: horizon, and needs at least :data:`HAZE_FAR_PIXELS` pixels there.
HAZE_FAR_ROWS, HAZE_FAR_PIXELS = 24, 20
#: :func:`road_haze`: a fit whose road colour without fog (``fog + (road - fog)``) lies more than this outside [0, 1]
#: is no fog curve (a nearly flat profile bent by a huge, unseen amplitude) and is refused.
HAZE_RANGE_SLACK = 0.05


def road_haze(image: Tensor, valid: Tensor, hole: Tensor, horizon: float, airlight: float = 0.25,
              lab: PictureLab | None = None) -> Tensor | None:
    """``(3, H)`` the road's colour per picture row around ``hole`` as fog or haze make it (None: no fit): the
    median colour of each row's road-like ``valid`` pixels (:func:`road_colours`, :func:`road_like`; columns
    thinned to about :data:`HAZE_COLUMNS`) below the ``horizon`` row within the hole's extent around it, fitted by
    ``fog + (road - fog) * exp(-k / r)`` (``r``: rows below the horizon, ``k`` from :data:`HAZE_DEPTHS`, ``fog``
    and ``road`` per channel by least squares); rows at or above the horizon take its value just below it. A clear
    road fits with ``fog`` near ``road`` (a flat profile); a fit whose far road is darker than its near road
    (shade, not haze) is None, and so is one whose road colour without fog lies outside [0, 1] (by more than
    :data:`HAZE_RANGE_SLACK`). Fog check: fog takes everything far to its own colour, so the far picture (the
    median colour of the ``valid`` pixels within ``height // HAZE_FAR_ROWS`` rows of the horizon, whatever they
    show) is the fog's colour; a fitted ``fog`` more than ``airlight`` from it in any channel is a far road lighter
    for another reason (a wet or glossy sheen, a lit patch, the end of a shade) and the fit is None, as it is when
    fewer than :data:`HAZE_FAR_PIXELS` such pixels are seen (1: no check). ``lab``: ``image``'s :class:`PictureLab`."""
    if lab is not None:
        lab.check(image)
    height, width = hole.shape
    ys, xs = nonzero_yx(hole)
    if not len(ys):
        return None
    extent = max(int(ys.max() - ys.min()), int(xs.max() - xs.min()), 20)
    rows = torch.arange(height, dtype=torch.float32)
    step = max(1, width // HAZE_COLUMNS)
    region = (dilate_square(hole, extent) & valid & (rows > horizon + 1)[:, None])[:, ::step]
    image = image[:, :, ::step]
    road, like = _road_around(image, region, lab=lab, step=step)
    if road is None:
        return None
    count = like.sum(1)
    use = (count >= HAZE_MIN_PIXELS).nonzero().flatten()
    if len(use) < HAZE_MIN_ROWS:
        return None
    cols = any_along(like, 0).nonzero().flatten()
    band = image[:, :, int(cols[0]):int(cols[-1]) + 1][:, use].float()  # (3, R, w)
    keep = like[use][:, int(cols[0]):int(cols[-1]) + 1]
    med = torch.where(keep[None], band, torch.full_like(band, float("nan"))).nanmedian(2).values.double()  # (3, R)
    weight = count[use].double().sqrt()
    depth = (rows[use].double() - horizon).clamp(min=1.0)
    best, fit = math.inf, None
    for k in HAZE_DEPTHS:
        x = torch.exp(-k / depth)
        design = torch.stack([torch.ones_like(x), x], 1) * weight[:, None]  # fog + (road - fog) * x
        sol = torch.linalg.lstsq(design, (med * weight).T).solution  # (2, 3): fog, road - fog
        err = float(((design @ sol - (med * weight).T) ** 2).sum())
        if err < best:
            best, fit = err, (k, sol)
    k, sol = fit
    if float(sol[1].mean()) > 0:  # the far road darker than the near one: shade, not haze
        return None
    own = sol[0] + sol[1]  # the road's colour without fog
    if float(own.min()) < -HAZE_RANGE_SLACK or float(own.max()) > 1 + HAZE_RANGE_SLACK:
        return None
    if airlight < 1:
        band = max(2, height // HAZE_FAR_ROWS)
        far = (valid & ((rows - horizon).abs() <= band)[:, None])[:, ::step]
        if count_set(far) < HAZE_FAR_PIXELS:
            return None
        seen = image[:, far].double().median(1).values  # (3,)
        if float((sol[0] - seen).abs().max()) > airlight:
            return None
    below = (rows.double() - horizon).clamp(min=1.0)
    return (sol[0][:, None] + sol[1][:, None] * torch.exp(-k / below)[None]).float()


#: Largest channel spread (max - min of sRGB) of a marking's colour: white or yellowish-grey paint, not a verge.
MARK_CHROMA = 0.12
#: Gaussian sigma (pixels) of the neighbourhood a marking is lighter than (a dash is a few pixels wide; a fog or
#: lighting gradient is as light as its neighbourhood at this scale).
MARK_SIGMA = 16.0


def _one_sided_marks(c_out: Tensor, c_in: Tensor, b_out: Tensor, b_in: Tensor, w_out: Tensor, w_in: Tensor,
                     both: Tensor, step: float) -> tuple[Tensor, Tensor]:
    """``(w_out, w_in)`` with the rays whose two sides disagree about a marking given to the unmarked side alone:
    where ``both (N,)`` sides were found and one side's colour ``(3, N)`` is near grey (:data:`MARK_CHROMA`) and
    more than ``step`` lighter in luma than its own neighbourhood (``b_out``, ``b_in``: the sources blurred at
    :data:`MARK_SIGMA`) while the other side is not. A dash seen on one side of the hole, interpolated towards plain
    road on the other, draws a long fading stripe along its line (the real frame's red car); a solid line seen on
    both sides still crosses the hole, and a fog gradient (as light as its neighbourhood) is no marking."""
    def sure(c: Tensor, b: Tensor) -> Tensor:  # 0 at half the step, 1 at the step: a ray grazing a dash's end is
        # partly marked (a hard cut draws the dash's end as a staircase)
        grey = (c.amax(0) - c.amin(0)) <= MARK_CHROMA
        return grey * ((luminance(c.T) - luminance(b.T)) / step * 2 - 1).clamp(0, 1)

    s_out, s_in = sure(c_out, b_out), sure(c_in, b_in)
    sure_out, sure_in = both * (s_out - s_in).clamp(min=0), both * (s_in - s_out).clamp(min=0)
    new_out, new_in = w_out * (1 - sure_out), w_in * (1 - sure_in)
    total = new_out + new_in
    keep = total <= 1e-6  # nothing left (a side at distance 0): as it was
    return (torch.where(keep, w_out, new_out / total.clamp(min=1e-6)),
            torch.where(keep, w_in, new_in / total.clamp(min=1e-6)))


#: :func:`verge_like`: Lab chroma distance from both the road's and grey beyond which a colour is no road (the
#: tolerance of :func:`road_like`), and the share of the road's lightness below which it is none either (the dark of a
#: hedge or a treeline, whose chroma is as small as grey's).
VERGE_CHROMA, VERGE_MIN_LIGHT = 12.0, 0.5
#: :func:`ray_fill` with ``verge='road'``: a ray's far side says the verge of its near side ended inside the hole only
#: where the far side is at least this share of the near side's distance from the vanishing point. Widths across the
#: road shrink with that distance: nearer the vanishing point a verge strip along the road is a few pixels wide, and a
#: vanishing point off by a degree misses it. On the real frame's black car the share was 0.7 (the verge did end: a
#: traffic island's tip); on the seed-31 tuning deletes whose lawn strips ran on behind a van, 0.23-0.26.
FAR_RESOLVED = 0.5


def verge_like(colours: Tensor, road: Tensor, tolerance: float = VERGE_CHROMA,
               min_light: float = VERGE_MIN_LIGHT) -> Tensor:
    """``(N,)`` bool: which ``colours (3, N)`` (sRGB) are no road for the road ``road (3,)`` (CIE Lab): their chroma
    farther than ``tolerance`` from both the road's and grey (a verge's grass, foliage, coloured paint), or their
    lightness under ``min_light`` of the road's (a hedge, a treeline in shade). Asphalt, its white or grey markings,
    kerbs and the road's lighter shadows are road."""
    # road_lab's columns converted where they lie (channel-major), not copied to rows and back: the same values
    lab = torch.from_numpy(_lab_columns(colours.float().contiguous().numpy())).T
    ab = lab[:, 1:]
    road = road.to(lab)
    return (((ab_length(ab - road[1:]) >= tolerance) & (ab_length(ab) >= tolerance))
            | (lab[:, 0] < min_light * road[0]))


def _verge_sides(c_out: Tensor, c_in: Tensor, both: Tensor, road: Tensor) -> tuple[Tensor, Tensor]:
    """``(near (N,), far (N,))`` bool: which rays' near side (away from the vanishing point: ``c_out (3, N)``, the
    sides' colours) and far side (``c_in``) is a verge (:func:`verge_like` of the road ``road (3,)``), among the rays
    ``both (N,)`` (both sides found; False elsewhere). :func:`ray_fill` with ``verge='road'`` fills a ray whose near
    side alone is a verge from its far side's road: the near side of a ray leaves the hole on the ground the removed
    car stood on or beside, and a verge there that the far side does not show ends inside the hole; a blend of the
    two is neither (the real frame's black car: the verge beside it blended into the far lane as a pale band). A
    verge on the far side only is left to the blend: for the hole's upper pixels the far side is often no ground at
    all (a hedge, a treeline, the horizon). Rays whose both sides are a verge: :func:`_ended_verge_runs`."""
    near, far = torch.zeros_like(both), torch.zeros_like(both)
    if any_set(both):
        near[both] = verge_like(c_out[:, both], road)
        far[both] = verge_like(c_in[:, both], road)
    return near, far


#: :func:`_continued_verge`: the verge is read on the ground pixels within ``VERGE_BAND`` pixels of the hole, its mask
#: smoothed over ``VERGE_SMOOTH`` (sigma, pixels: a lawn's grain of road-coloured specks is no edge), and a ray's near
#: side meets the verge's edges within ``VERGE_EDGE_REACH`` pixels of it.
VERGE_BAND, VERGE_RIM, VERGE_SMOOTH, VERGE_EDGE_REACH = 8, 2, 1.5, 32.0


def _continued_verge(image: Tensor, valid: Tensor, hole: Tensor, road: Tensor, ground_row: float, pix: Tensor,
                     q_out: Tensor) -> Tensor:
    """``(N,)`` bool: which hole pixels ``pix (N, 2)`` (x, y) lie inside the verge their ray's near side
    ``q_out (N, 2)`` shows, its edges continued straight into the hole: on the verge's side of every edge line of the
    verge (:func:`verge_like` of the road ``road (3,)``, on the ``valid`` pixels within :data:`VERGE_BAND` of ``hole
    (H, W)`` from row ``ground_row`` down, smoothed) within :data:`VERGE_EDGE_REACH` of ``q_out``. A verge's edge
    that runs into the hole runs on inside it: the real frame's black car hid a traffic island whose two edges meet
    in a tip the far side shows, and a ray from the island's grass to the far lane's road crosses the island's edge
    inside the hole, not where the hole begins. No edge near ``q_out``: False (nothing says where the verge ends)."""
    import cv2

    height, width = hole.shape
    inside = torch.zeros(len(pix), dtype=torch.bool)
    rows, cols = any_along(hole, 1).nonzero().flatten(), any_along(hole, 0).nonzero().flatten()
    y0, y1, x0, x1 = padded_window(rows, cols, VERGE_BAND + 3, (height, width))
    h = hole[y0:y1, x0:x1]
    rows = torch.arange(y0, y1, dtype=torch.float32)[:, None]
    # the hole's rim is no evidence: a mask's edge leaves the removed car's blended outline there
    band = dilate_square(h, VERGE_BAND) & ~dilate_square(h, VERGE_RIM) & valid[y0:y1, x0:x1] & (rows >= ground_row)
    by, bx = nonzero_yx(band)
    if not len(by):
        return inside
    verge = torch.zeros_like(band)
    verge[by, bx] = verge_like(image[:, y0:y1, x0:x1][:, by, bx], road)
    w = band.float().numpy()
    share = cv2.GaussianBlur(verge.float().numpy() * w, (0, 0), VERGE_SMOOTH) / np.maximum(
        cv2.GaussianBlur(w, (0, 0), VERGE_SMOOTH), 1e-6)
    mask = (share > 0.5) & w.astype(bool)
    # an edge pixel: in the verge, beside a band pixel that is not; its normal points out of the verge (down the share)
    beside = dilate_cross(torch.from_numpy(~mask & w.astype(bool))).numpy()  # a 4-neighbour of the road side
    ey, ex = np.nonzero(mask & beside)
    if not len(ey):
        return inside
    gy, gx = np.gradient(share)
    normal = -np.stack([gx[ey, ex], gy[ey, ex]], 1)
    length = np.linalg.norm(normal, axis=1)
    keep = length > 1e-3
    if not keep.any():
        return inside
    edge = torch.from_numpy(np.stack([ex[keep] + x0, ey[keep] + y0], 1).astype(np.float32))
    normal = torch.from_numpy((normal[keep] / length[keep, None]).astype(np.float32))
    offset = (edge * normal).sum(1)  # each edge line: normal . x = offset
    for s in range(0, len(pix), RAY_CHUNK):  # in chunks: (chunk, K) at a time, not (N, K)
        near = torch.cdist(q_out[s:s + RAY_CHUNK], edge) <= VERGE_EDGE_REACH
        side = pix[s:s + RAY_CHUNK] @ normal.T - offset  # > 0 on the road's side of an edge
        side = torch.where(near, side, torch.full_like(side, -math.inf))
        inside[s:s + RAY_CHUNK] = near.any(1) & (side.amax(1) < 0)
    return inside


def _ended_verge_runs(angle: Tensor, reach: Tensor, near: Tensor, far: Tensor) -> Tensor:
    """``(N,)`` bool: the rays whose both sides are a verge (``near``, ``far``: :func:`_verge_sides`) that
    :func:`ray_fill` with ``verge='road'`` fills from the far side's road all the same: those inside a run of rays
    (adjacent ``angle (N,)`` about the vanishing point, in steps of one pixel at the median ``reach (N,)`` of the
    near-verge rays) whose near side is a verge and whose far side, for most of them, is road. A verge strip along the
    road keeps its angle about the vanishing point along its whole length, so its rays see it on both sides; where
    most rays of a near-side verge find road on their far side the verge ended inside the hole, and the few that meet
    another verge there met something else (the real frame's black car: a traffic island beside it and the island's
    tip beyond it, which the blend joined by a thin pale line across the far lane)."""
    if not any_set(near):
        return torch.zeros_like(near)
    step = 1.0 / float(reach[near].median().clamp(min=1.0))
    bins = ((angle[near] - angle[near].min()) / step).floor().long()
    occupied = torch.zeros(int(bins.max()) + 1, dtype=torch.bool)
    occupied[bins] = True
    run = torch.cumsum((~occupied).long(), 0)[bins]  # the same id for every bin of a run of occupied bins
    runs = int(run.max()) + 1
    both = far[near].float()
    ended_runs = torch.zeros(runs).index_add_(0, run, 1 - both) > torch.zeros(runs).index_add_(0, run, both)
    out = torch.zeros_like(near)
    out[near] = far[near] & ended_runs[run]
    return out


#: Grain weights :func:`ray_fill` chooses from with ``match_grain``, increasing (:func:`_nearest_zero` bisects them).
GRAIN_WEIGHTS = (0.0, 0.125, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0)


def _luma_laplacian(image: Tensor) -> Tensor:
    """``(H, W)`` absolute 3x3 Laplacian of the luma of ``image (3, H, W)`` (the texture measure of the records: its
    mean over a region)."""
    import cv2

    y = (image.permute(1, 2, 0).float().numpy() @ np.array([0.2126, 0.7152, 0.0722], np.float32)).astype(np.float32)
    return torch.from_numpy(np.abs(cv2.Laplacian(np.ascontiguousarray(y), cv2.CV_32F, ksize=1)))


def _matched_weight(image: Tensor, valid: Tensor, values: Tensor, grains: Tensor, ys: Tensor, xs: Tensor,
                    default: float, lab: PictureLab | None = None) -> float:
    """The weight of :data:`GRAIN_WEIGHTS` at which the road-like pixels of the fill
    ``values + weight * grains`` (both ``(3, N)`` at hole pixels ``ys, xs``; those with no picture pixel in their
    3x3 neighbourhood: the seam is not grain) have the mean absolute luma Laplacian of the road-like ``valid``
    pixels 8 to 40 pixels around the hole (:func:`road_like`: asphalt and its markings,
    not grass or foliage). ``default`` where too few such pixels are found. ``lab``: ``image``'s
    :class:`PictureLab`."""
    height, width = valid.shape
    hole = torch.zeros_like(valid)
    hole[ys, xs] = True
    ring = dilate_square(hole, 40) & ~dilate_square(hole, 8) & valid
    road, around = _road_around(image, ring, lab=lab)
    if road is None:
        return default
    if count_set(around) < 50:
        return default
    y0, y1 = max(int(ys.min()) - 41, 0), min(int(ys.max()) + 42, height)
    x0, x1 = max(int(xs.min()) - 41, 0), min(int(xs.max()) + 42, width)
    target = float(_luma_laplacian(image[:, y0:y1, x0:x1].float())[around[y0:y1, x0:x1]].mean())
    # hole pixels whose 3x3 neighbourhood is all hole (the picture's outside counts as hole): on the box grown by one
    wy0, wy1, wx0, wx1 = max(int(ys.min()) - 1, 0), int(ys.max()) + 2, max(int(xs.min()) - 1, 0), int(xs.max()) + 2
    inside = (~dilate_square(~hole[wy0:wy1, wx0:wx1], 1))[ys - wy0, xs - wx0]  # (N,)
    if count_set(inside) < 50:
        return default
    # The pixels looked at have only hole pixels in their 3x3 neighbourhood: the box of those grown by one holds it.
    iy, ix = ys[inside], xs[inside]
    y0, y1 = max(int(iy.min()) - 1, 0), min(int(iy.max()) + 2, height)
    x0, x1 = max(int(ix.min()) - 1, 0), min(int(ix.max()) + 2, width)
    box = (ys >= y0) & (ys < y1) & (xs >= x0) & (xs < x1)
    values, grains, ys, xs, inside = values[:, box], grains[:, box], ys[box], xs[box], inside[box]
    crop = image[:, y0:y1, x0:x1].float().clone()
    at = (ys - y0) * (x1 - x0) + (xs - x0)  # the hole pixels in the crop, flat
    at_inside = at[inside]
    crop_flat, at_np = crop.view(3, -1).numpy(), at.numpy()
    levels: dict[int, float | None] = {}

    def excess(i: int) -> float | None:
        """The fill's texture at weight ``GRAIN_WEIGHTS[i]`` less the target (None: too few road-like pixels)."""
        if i not in levels:
            filled = (values + GRAIN_WEIGHTS[i] * grains).clamp(0, 1)
            crop_flat[:, at_np] = filled.numpy()  # NumPy's assignment: the same values, faster than torch's
            # road_like is per pixel: looked at on the hole's pixels alone (the cost: a Lab conversion per weight)
            like = road_like(filled[:, inside, None], road)[:, 0]
            levels[i] = (float(_luma_laplacian(crop).view(-1)[at_inside[like]].mean()) - target
                         if count_set(like) >= 50 else None)
        return levels[i]

    chosen = _nearest_zero(excess, len(GRAIN_WEIGHTS))
    return default if chosen is None else GRAIN_WEIGHTS[chosen]


def _nearest_zero(excess: Callable[[int], float | None], count: int) -> int | None:
    """The index ``i < count`` whose ``excess(i)`` is nearest 0 (the first on ties; None: every one is None), the
    excesses taken to grow with ``i`` (more grain, more texture): the ends first, then a bisection for the sign
    change, so at most ``2 + ceil(log2(count - 1))`` of them are computed (6 of 10). Where one of those is None (the
    monotone reading cannot be trusted), they do not grow, or the last two are equal (the first of equal ones is
    wanted), every index is looked at, in order."""
    lo, hi = 0, count - 1
    first, last = excess(lo), excess(hi)
    monotone = first is not None and last is not None and first <= last
    if monotone and (first >= 0 or first == last):  # first == last: all equal (no grain where it is measured)
        return lo
    if monotone and last <= 0:
        before = excess(hi - 1)
        if before is not None and before < last:
            return hi
        monotone = False  # a tie or no growth at the end
    while monotone and hi - lo > 1:  # excess(lo) < 0 < excess(hi)
        mid = (lo + hi) // 2
        e = excess(mid)
        if e is None or not first <= e <= last:
            monotone = False
        elif e < 0:
            lo, first = mid, e
        else:
            hi, last = mid, e
    if monotone:
        return lo if -first <= last else hi
    best, gap = None, math.inf
    for i in range(count):
        e = excess(i)
        if e is not None and abs(e) < gap:
            best, gap = i, abs(e)
    return best


def _mirrored(detail: Tensor, valid: Tensor, edge: Tensor, back: Tensor, depth: Tensor,
              kept: Tensor | None = None) -> tuple[Tensor, Tensor]:
    """``(grain (3, N), ok (N,))``: ``detail`` at ``edge + back * folded depth`` (nearest pixel: interpolation would
    average the grain away), the ``depth (N,)`` into the hole folded into ``[0, GRAIN_FOLD]`` (a triangle wave, so a
    deep pixel reads near the edge, where the road is, not far beyond it); ``ok``: that pixel is ``valid``.
    ``kept (H, W)`` bool (None: all): ``detail * kept`` is read, multiplied at the pixels read only (the same
    product of each, without the whole picture's)."""
    height, width = valid.shape
    folded = GRAIN_FOLD - (depth.remainder(2 * GRAIN_FOLD) - GRAIN_FOLD).abs()
    mirror = edge + back * folded[:, None]
    mx, my = mirror[:, 0].round().long(), mirror[:, 1].round().long()
    inside = (mx >= 0) & (mx < width) & (my >= 0) & (my < height)
    # read at flat indices (one index_select per picture, not two index tensors' advanced indexing): the same pixels
    at = my.clamp_(0, height - 1).mul_(width).add_(mx.clamp_(0, width - 1))
    grain = detail.reshape(len(detail), -1).index_select(1, at)
    if kept is not None:
        grain = grain * kept.reshape(-1).index_select(0, at)
    return grain, inside & valid.reshape(-1).index_select(0, at)


def _along(image: Tensor, valid: Tensor, start: Tensor, unit: Tensor, span: int) -> Tensor:
    """``(3, N)`` mean of ``image`` at the ``valid`` ones of the ``span`` points ``start + k unit`` (k = 0, 1, ...;
    the first is valid by construction, so the mean always has a term). All points are sampled in one call; the
    sum runs over ``k`` in order, as a loop over the points would."""
    if span <= 1:
        return _gather(image, start)
    height, width = valid.shape
    n = len(start)
    q, ok = _along_points(start, unit, valid, span)
    samples = _gather(image, q).mul_(ok)  # (3, span * N), each point's term (0 where not valid)
    total = torch.zeros(3, n)
    for k in range(span):
        total += samples[:, k * n:(k + 1) * n]
    count = ok.view(span, n).sum(0)  # whole numbers: exact in any order
    return total / count.clamp(min=1)


def _along_points(start: Tensor, unit: Tensor, valid: Tensor, span: int) -> tuple[Tensor, Tensor]:
    """``(points (span * N, 2), ok (span * N,))``: :func:`_along`'s points ``start + k unit``, the ``k``-th block of
    ``N`` rows for ``k``, and which of them round to a ``valid (H, W)`` pixel inside the picture (the first block:
    all). By the C++ kernel (:func:`ray_kernel`: the same float32 product, sum and rounding, in one pass without
    torch's temporaries) where it is built, else by torch."""
    height, width = valid.shape
    n = len(start)
    f32 = start.dtype == torch.float32 and unit.dtype == torch.float32 and valid.dtype == torch.bool
    kernel = ray_kernel() if f32 and n else None
    if kernel is not None:
        start, unit = start.contiguous(), unit.contiguous()
        mask = valid.contiguous().view(torch.uint8)
        q = torch.empty(span * n, 2, dtype=torch.float32)
        ok = torch.empty(span * n, dtype=torch.bool)
        kernel.sdn3d_ray_along_f32(start.data_ptr(), unit.data_ptr(), mask.data_ptr(), height, width, span, n,
                                   q.data_ptr(), ok.data_ptr())
        return q, ok
    q = torch.cat([start + k * unit for k in range(span)])  # (span * N, 2)
    x, y = q[:, 0].round().long(), q[:, 1].round().long()
    ok = (x >= 0) & (x < width) & (y >= 0) & (y < height) & valid.reshape(-1)[
        y.clamp(0, height - 1) * width + x.clamp(0, width - 1)]
    ok[:n] = True
    return q, ok


def _gather(image: Tensor, points: Tensor) -> Tensor:
    """``(3, N)`` bilinear samples of ``image (3, H, W)`` at ``points (N, 2)`` (x, y pixels; border-clamped)."""
    height, width = image.shape[1:]
    # both coordinates at once (x / (W - 1) * 2 - 1, y / (H - 1) * 2 - 1: the same quotient, product and difference
    # of each as one column at a time), already laid out as the grid: no stack of the columns
    scale = torch.tensor([max(width - 1, 1), max(height - 1, 1)], dtype=points.dtype)
    grid = (points / scale * 2 - 1).view(1, 1, -1, 2).to(image.dtype)
    return F.grid_sample(image[None], grid, mode="bilinear", padding_mode="border", align_corners=True)[0, :, 0]


def shadowed_road(image: Tensor, road: Tensor, within: Tensor, lit: Tensor, light_share: float = 0.8,
                  tolerance: float = 12.0, lab: PictureLab | None = None) -> Tensor:
    """``(H, W)`` bool pixels inside ``within`` whose :func:`road_shade` is under ``light_share``: road in shadow (a
    car's, a tree's), which a ray must not carry into a hole."""
    return road_shade(image, road, within, lit, tolerance, lab) < light_share


def road_shade(image: Tensor, road: Tensor, within: Tensor, lit: Tensor, tolerance: float = 12.0,
               lab: PictureLab | None = None, luma: bool = False, local: float = 0.0) -> Tensor:
    """``(H, W)`` float32: each pixel's lightness over the road's on its row, for the pixels inside ``within`` whose
    chroma is the road's (``road (3,)`` Lab, :func:`road_like`; scaled by the pixel's lightness over the road's, as
    a shadow's chroma shrinks with its light); NaN elsewhere. The road's lightness per row is the median of the
    road-like ``lit (H, W)`` pixels there (rows without any: the nearest row with some), since haze and fog lighten
    the road with distance, that is with the row. Lightness is CIE L, or with ``luma`` the Rec. 709 luma of the sRGB
    values (a gain on them brings a pixel to the road's: :func:`~sdn3d.editing.photo.fill.relight_faint_shadow`).
    ``local`` > 0: the road's lightness is the darker of its row's and the lit road's beside the pixel (their mean
    weighted by a Gaussian of sigma ``local`` pixels along the row, 1 pixel across rows, as fog lightens the road
    with the row; the row's alone where under 5 % of that window is lit road): a road lit unevenly along its rows
    (the real frame of ``tests/data``: its road darkens to the right) is not taken for shade there.
    ``lab``: ``image``'s :class:`PictureLab` (the same values, converted once for all the removal's tests)."""
    if lab is not None:
        lab.check(image)
    out = torch.full(tuple(within.shape), float("nan"))
    box = _box(within | lit)
    if box is None:
        return out
    y0, y1, x0, x1 = box
    rows = (road_lab(image[:, y0:y1, x0:x1].permute(1, 2, 0).reshape(-1, 3)) if lab is None
            else lab.box(y0, y1, x0, x1))
    lab = rows.view(y1 - y0, x1 - x0, 3)
    light = lab[..., 0]
    # A shadow's chroma shrinks with its lightness (the road's colour times less light): compared at that scale.
    scale = (light / max(abs(float(road[0])), 1e-3)).clamp(0, 1)[..., None]
    like = ab_length(lab[..., 1:] - road[1:].to(lab) * scale) < tolerance
    ref_px = like & lit[y0:y1, x0:x1]
    rows = any_along(ref_px, 1)
    if not any_set(rows):
        return out
    if luma:
        light = luminance(image[:, y0:y1, x0:x1].permute(1, 2, 0).float())
    per_row = torch.where(ref_px, light, torch.full_like(light, float("nan"))).nanmedian(1).values
    have = rows.nonzero().flatten()
    nearest = have[(torch.arange(y1 - y0)[:, None] - have[None]).abs().argmin(1)]
    ref = per_row[nearest][:, None].expand_as(light)
    if local > 0:
        # Read only on `within`'s rows: blurred on those and the rows the blur reaches from them (its wide kernel
        # along the rows took about 60 ms on the whole box of the real frame's removals, whose zone is its bottom
        # quarter). Each row's horizontal pass is its own and the vertical pass reads only rows inside the cut (or
        # at the box's edge, as before): OpenCV gives the same bits there.
        wanted = any_along(within[y0:y1, x0:x1], 1).nonzero().flatten()
        if len(wanted):
            across = 1.0  # the blur's sigma down the rows: its reach sets the rows blurred
            reach = _blur_reach(across)
            r0, r1 = max(int(wanted[0]) - reach, 0), min(int(wanted[-1]) + 1 + reach, y1 - y0)
            mean, weight = _masked_blur(light[None, r0:r1], ref_px[r0:r1], local, sigma_y=across)
            ref = ref.contiguous()
            ref[r0:r1] = torch.where(weight >= 0.05, torch.minimum(mean[0].to(ref), ref[r0:r1]), ref[r0:r1])
    share = (light / ref.clamp(min=1e-3)).float()
    out[y0:y1, x0:x1] = torch.where(like & within[y0:y1, x0:x1], share, torch.full_like(share, float("nan")))
    return out


def road_lab(rgb: Tensor) -> Tensor:
    """``(P, 3)`` float32 CIE Lab (D65) of sRGB rows ``rgb (P, 3)`` in [0, 1], channel-major as
    :func:`~sdn3d.editing.photo.recolor.srgb_to_lab` returns them: its formula and constants (kornia's), computed by
    NumPy with a true cube root (``np.cbrt`` for ``pow(x, 1 / 3)``). Within about 2e-4 of ``srgb_to_lab``, not bit for
    bit, at under half its cost: torch's ``pow`` took most of the fill's road tests (:func:`road_colours`,
    :func:`road_like`, :func:`shadowed_road`: hundreds of thousands of pixels per edit at 1242x375), whose
    thresholds are whole Lab units.

    >>> [round(v, 2) for v in road_lab(torch.tensor([[1.0, 0.0, 0.0]]))[0].tolist()]
    [53.24, 80.09, 67.2]
    """
    return torch.from_numpy(_lab_columns(rgb.float().T.numpy())).T


def _lab_columns(rgb: np.ndarray) -> np.ndarray:
    """``(3, P)`` float32 C-contiguous Lab of the sRGB columns ``rgb (3, P)`` float32 (any layout; clipped to [0, 1]):
    :func:`road_lab`'s arithmetic. Every column's Lab is its own pixel's alone, bit for bit wherever it stands among
    the others (NumPy's ``power`` and ``cbrt`` give the same bits at any position), which :class:`PictureLab` relies
    on."""
    return _lab_of_linear(_linear_rgb(rgb))


def _linear_rgb(rgb: np.ndarray) -> np.ndarray:
    """``(3, P)`` float32 linear RGB of the sRGB columns ``rgb (3, P)`` (clipped to [0, 1]): :func:`road_lab`'s first
    step, value by value."""
    x = np.clip(rgb, 0.0, 1.0)
    f32 = np.float32
    return np.where(x > f32(0.04045), np.power((x + f32(0.055)) / f32(1.055), f32(2.4)), x / f32(12.92))


#: :func:`_linear_rgb` of the 256 levels of an 8-bit picture (``level / 255`` in float32, as torch divides them).
_LINEAR_LEVELS = _linear_rgb((torch.arange(256, dtype=torch.float32) / 255).numpy())


def _linear_of_levels(levels: np.ndarray) -> np.ndarray:
    """``(3, P)`` float32 :data:`_LINEAR_LEVELS` of the 8-bit values ``levels (3, P)``: ``np.take(_LINEAR_LEVELS,
    levels)``, the same table entries, looked up by OpenCV's ``LUT`` (a third of ``take``'s time, which first widens
    every uint8 index to 64 bits)."""
    if not levels.size:
        return np.take(_LINEAR_LEVELS, levels)
    import cv2

    return cv2.LUT(levels, _LINEAR_LEVELS)


def _lab_of_linear(lin: np.ndarray) -> np.ndarray:
    """``(3, P)`` float32 C-contiguous Lab of the linear RGB columns ``lin (3, P)`` (:func:`_linear_rgb`)."""
    from sdn3d.editing.photo.recolor import _RGB_TO_XYZ, _WHITE

    f32 = np.float32
    m = np.asarray(_RGB_TO_XYZ, np.float32) / np.asarray(_WHITE, np.float32)[:, None]
    # the 3x3 product as sums of products: NumPy's matrix product runs on OpenBLAS' own threads, whatever torch's count
    xyz = np.stack([m[i, 0] * lin[0] + m[i, 1] * lin[1] + m[i, 2] * lin[2] for i in range(3)])
    f = np.where(xyz > f32(0.008856), np.cbrt(xyz), f32(7.787) * xyz + f32(4.0 / 29.0))
    return np.stack([f32(116.0) * f[1] - f32(16.0), f32(500.0) * (f[0] - f[1]), f32(200.0) * (f[1] - f[2])])


class PictureLab:
    """The :func:`road_lab` of one picture's pixels, each converted on its first use and kept: the removal's road tests
    (:func:`road_colours`, :func:`shadowed_road`, :func:`road_haze`, :func:`_matched_weight`) look at overlapping
    parts of the same picture, and an editor's later removals from the same source at more of them
    (:class:`~sdn3d.editing.photo.transfer.PhotoSource` keeps one). Every value is bit for bit the ``road_lab`` of
    the same pixels converted on their own (:func:`_lab_columns`).

    Args:
        image: ``(3, H, W)`` float32 CPU picture in [0, 1]; it must not change while this is in use.
        levels: ``(3, H, W)`` uint8, the 8-bit picture ``image`` is ``levels / 255`` of (float32, torch's division),
            or None. With it, each value's linear RGB is looked up among the 256 levels' (:data:`_LINEAR_LEVELS`, the
            same bits) instead of computed by ``power``, a fifth of a conversion's cost.
    """

    def __init__(self, image: Tensor, levels: Tensor | None = None) -> None:
        if image.dim() != 3 or image.shape[0] != 3 or image.dtype != torch.float32 or image.device.type != "cpu":
            raise ValueError(f"PictureLab: image must be a (3, H, W) float32 CPU picture, got {tuple(image.shape)} "
                             f"{image.dtype} on {image.device}")
        if levels is not None and (levels.dtype != torch.uint8 or levels.shape != image.shape):
            raise ValueError(f"PictureLab: levels must be uint8 of the image's shape {tuple(image.shape)}, got "
                             f"{tuple(levels.shape)} {levels.dtype}")
        self.image = image
        self._rgb = image.detach().numpy()
        self._levels = None if levels is None else levels.numpy()
        self._lab = np.zeros(self._rgb.shape, np.float32)
        self._done = np.zeros(self._rgb.shape[1:], bool)

    def check(self, image: Tensor) -> None:
        """Raises ValueError unless this is the Lab of ``image`` (the very tensor it was made from)."""
        if image is not self.image:
            raise ValueError("PictureLab is of another picture than the one given (lab= must be the image's own)")

    def _convert(self, y0: int, x0: int, need: np.ndarray | None, h: int = 0, w: int = 0) -> None:
        """Converts the not yet converted ``need (h, w)`` pixels (None: all) of the box at ``(y0, x0)``: the whole box
        at once where they are at least half of it (a pixel converted again gets the same bits; NumPy's boolean
        selection and assignment of a picture's pixels cost more than converting the others)."""
        if need is not None:
            h, w = need.shape
        done = self._done[y0:y0 + h, x0:x0 + w]
        todo = ~done if need is None else need & ~done
        count = int(np.count_nonzero(todo))
        if not count:
            return
        src = self._rgb if self._levels is None else self._levels
        rgb, lab = src[:, y0:y0 + h, x0:x0 + w], self._lab[:, y0:y0 + h, x0:x0 + w]
        if 2 * count >= h * w:
            lab[...] = self._lab_of(rgb.reshape(3, -1)).reshape(3, h, w)
            done[...] = True
        else:
            lab[:, todo] = self._lab_of(rgb[:, todo])
            done |= todo

    def _lab_of(self, values: np.ndarray) -> np.ndarray:
        """``(3, P)`` Lab of the picture's values ``(3, P)`` (its levels when it has them)."""
        if self._levels is None:
            return _lab_columns(values)
        return _lab_of_linear(_linear_of_levels(values))

    def pixels(self, mask: Tensor, step: int = 1) -> Tensor:
        """``(N, 3)`` float32 Lab of the ``mask`` pixels in the picture's order, laid out as :func:`road_lab` returns
        them: ``road_lab(image[:, :, ::step][:, mask].T)`` bit for bit. ``mask (H, ceil(W / step))`` bool: on every
        ``step``-th column of the picture."""
        m = mask.numpy()
        height, width = self._done.shape
        if m.shape != (height, len(range(0, width, step))):
            raise ValueError(f"PictureLab.pixels: mask {m.shape} is not of the picture {(height, width)} "
                             f"thinned to every {step}-th column")
        full = m if step == 1 else np.zeros((height, width), bool)
        if step != 1:
            full[:, ::step] = m
        box = _box(torch.from_numpy(full))
        if box is None:
            return torch.zeros(3, 0).T
        y0, y1, x0, x1 = box
        self._convert(y0, x0, full[y0:y1, x0:x1])
        # (3, N) C-contiguous as road_lab makes it; NumPy's compress selects along one axis 6x faster than a mask index
        return torch.from_numpy(np.compress(full.reshape(-1), self._lab.reshape(3, -1), axis=1)).T

    def box(self, y0: int, y1: int, x0: int, x1: int) -> Tensor:
        """``(h * w, 3)`` float32 Lab of the box's pixels row by row, laid out as :func:`road_lab` returns them:
        ``road_lab(image[:, y0:y1, x0:x1].permute(1, 2, 0).reshape(-1, 3))`` bit for bit."""
        self._convert(y0, x0, None, y1 - y0, x1 - x0)
        return torch.from_numpy(self._lab[:, y0:y1, x0:x1].copy().reshape(3, -1)).T


def ab_length(ab: Tensor) -> Tensor:
    """``(...)`` the Euclidean length of ``ab (..., 2)`` (a Lab chroma difference), equal bit for bit to
    ``ab.norm(dim=-1)``. Lab rows from :func:`~sdn3d.editing.photo.recolor.srgb_to_lab` are channel-major, and torch
    reduces such a non-contiguous last dimension with a scalar loop (``sqrt(a * a + b * b)``, each step rounded in
    the tensor's precision) that took a fifth of a second per edit at 1242x375; NumPy does the same arithmetic,
    vectorised. A contiguous last dimension takes torch's own norm (its vectorised reduction rounds differently)."""
    if ab.stride(-1) == 1 or ab.requires_grad or ab.device.type != "cpu":
        return ab.norm(dim=-1)
    a, b = ab[..., 0].numpy(), ab[..., 1].numpy()
    return torch.from_numpy(np.sqrt(a * a + b * b))


def _box(mask: Tensor) -> tuple[int, int, int, int] | None:
    """``(y0, y1, x0, x1)`` the half-open box of the ``mask (H, W)`` pixels (None: none), from NumPy's ``any`` (torch's
    ``any`` or ``nonzero`` of a whole picture's mask take 0.3-0.5 ms)."""
    m = mask.numpy()
    rows = np.flatnonzero(m.any(1))
    if not len(rows):
        return None
    cols = np.flatnonzero(m.any(0))
    return int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1


def road_colours(image: Tensor, ring: Tensor, tolerance: float = 12.0,
                 lab: PictureLab | None = None) -> Tensor | None:
    """``(3,)`` Lab of the road around a removed object: the median of the ``ring (H, W)`` pixels (around it, on
    no object) that are near grey or near the ring's own median chroma; None with fewer than 30 such pixels.
    ``lab``: ``image``'s :class:`PictureLab` (the same values, converted once for all the removal's tests)."""
    if lab is not None:
        lab.check(image)
    if count_set(ring) < 30:
        return None
    return _road_of(_ring_lab(image, ring, lab), tolerance)


def _ring_lab(image: Tensor, ring: Tensor, lab: PictureLab | None, step: int = 1) -> Tensor:
    """``(N, 3)`` :func:`road_lab` of the ``ring (H, W)`` pixels of ``image (3, H, W)`` in the picture's order, from
    ``lab`` (``image``'s :class:`PictureLab`, of the picture before its columns were thinned to every ``step``-th)
    when given."""
    if lab is None:
        # road_lab of the ring's pixels, selected by NumPy's compress straight into the channel-major columns that
        # road_lab converts (the same values: each column's Lab is its own pixel's alone, _lab_columns)
        picked = np.compress(ring.numpy().reshape(-1), image.float().reshape(3, -1).numpy(), axis=1)
        return torch.from_numpy(_lab_columns(picked)).T
    return lab.pixels(ring, step)


def _road_of(lab: Tensor, tolerance: float) -> Tensor | None:
    """:func:`road_colours` of the ring pixels' Lab rows ``lab (N, 3)``."""
    ab = lab[:, 1:]
    inner = ab_length(ab) < 2 * tolerance
    if count_set(inner) < 30:
        return None
    mid = _selected_median(ab, inner)
    near = ab_length(ab - mid) < tolerance
    return _selected_median(lab, near) if count_set(near) >= 30 else None


def _selected_median(x: Tensor, rows: Tensor) -> Tensor:
    """``(C,)`` :func:`_column_median` of the ``rows (N,)`` rows of a NaN-free ``x (N, C)`` (some selected), the same
    values: for a channel-major ``x`` (``x.T`` contiguous, as :func:`road_lab` makes Lab rows), each column selected
    by NumPy's ``compress`` and, from :data:`MEDIAN_NUMPY_MIN` rows on, partitioned where it lies (torch's selection
    of a channel-major ``(N, 3)`` and a partition down its columns' stride took twice as long)."""
    cm = x.T
    if x.requires_grad or x.device.type != "cpu" or not cm.is_contiguous():
        return _column_median(x[rows])
    picked = np.compress(rows.numpy(), cm.numpy(), axis=1)  # (C, M), each column's values in order
    if picked.shape[1] < MEDIAN_NUMPY_MIN:
        return _column_median(torch.from_numpy(picked).T)
    k = (picked.shape[1] - 1) // 2  # the lower middle, as _column_median's (the k-th smallest: one value)
    return torch.from_numpy(np.partition(picked, k, axis=1)[:, k].copy())


def _road_around(image: Tensor, ring: Tensor, tolerance: float = 12.0, lab: PictureLab | None = None,
                 step: int = 1) -> tuple[Tensor | None, Tensor]:
    """``(road, like (H, W))``: :func:`road_colours` of ``ring`` and its pixels :func:`road_like` of that road (the
    ``ring`` pixels within ``tolerance`` of its chroma, lightness at least 0; all False when ``road`` is None), both
    from one Lab conversion of the ring's pixels (``road_like`` converted the ring's whole box again); ``lab``: the
    :class:`PictureLab` of the picture ``image`` is every ``step``-th column of."""
    like = torch.zeros(ring.shape, dtype=torch.bool)
    if count_set(ring) < 30:
        return None, like
    lab = _ring_lab(image, ring, lab, step)
    road = _road_of(lab, tolerance)
    if road is not None:
        like[ring] = _near_road(lab, road, tolerance, 0.0)
    return road, like


#: :func:`_column_median` selects with NumPy from this many rows on (torch's median is faster below, slower above).
MEDIAN_NUMPY_MIN = 8192


def _column_median(x: Tensor) -> Tensor:
    """``(C,)`` ``x.median(0).values`` of a NaN-free ``x (N, C)``, ``N >= 1``: the lower middle element of each column,
    selected by NumPy's partition from :data:`MEDIAN_NUMPY_MIN` rows on (twice as fast there)."""
    if len(x) < MEDIAN_NUMPY_MIN or x.requires_grad or x.device.type != "cpu":
        return x.median(0).values
    k = (len(x) - 1) // 2
    return torch.from_numpy(np.partition(x.numpy(), k, axis=0)[k].copy())


def _masked_median(x: Tensor, mask: Tensor) -> float:
    """``float(x[mask].median())`` for a float CPU ``x (H, W)`` and a ``mask (H, W)`` with some True: the lower middle
    of the selected values, selected and partitioned by NumPy (torch's boolean selection alone took 10 ms of a
    1242x375 picture's 15 ms); with a NaN among them, torch's (its median is NaN)."""
    if x.requires_grad or x.device.type != "cpu":
        return float(x[mask].median())
    values = x.numpy()[mask.numpy()]
    if np.isnan(values).any():
        return float(x[mask].median())
    return float(_column_median(torch.from_numpy(values)[:, None])[0])


def road_like(image: Tensor, road: Tensor, tolerance: float = 12.0, min_light: float = 0.0,
              within: Tensor | None = None) -> Tensor:
    """``(H, W)`` bool: pixels whose chroma (Lab a, b) is within ``tolerance`` of the road's ``road (3,)`` and whose
    lightness is at least ``min_light`` of its: asphalt and its grey or white lane markings (with ``min_light`` 0,
    its shadows too); not grass, foliage or paint. ``within (H, W)``: only the box around those pixels is looked at
    (False outside it)."""
    out = torch.zeros(image.shape[1:], dtype=torch.bool)
    y0, y1, x0, x1 = 0, image.shape[1], 0, image.shape[2]
    if within is not None:
        box = _box(within)
        if box is None:
            return out
        y0, y1, x0, x1 = box
    crop = image[:, y0:y1, x0:x1]
    lab = road_lab(crop.permute(1, 2, 0).reshape(-1, 3))
    out[y0:y1, x0:x1] = _near_road(lab, road, tolerance, min_light).view(crop.shape[1:])
    return out


def _near_road(lab: Tensor, road: Tensor, tolerance: float, min_light: float) -> Tensor:
    """``(N,)`` bool: which Lab rows ``lab (N, 3)`` are road-like for the road ``road (3,)`` (:func:`road_like`'s
    test: chroma within ``tolerance``, lightness at least ``min_light`` of the road's)."""
    return (ab_length(lab[:, 1:] - road[1:]) < tolerance) & (lab[:, 0] >= min_light * road[0])
