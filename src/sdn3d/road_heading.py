"""The road's direction in a picture: the vanishing point its edges vote for, and the road's axis near each object.

In a driving scene lane markings, kerbs, verges and guard rails run along the road, and in a pinhole picture their
lines meet at the road's vanishing point on the horizon. :func:`image_vanishing_point` finds it from the picture's
line-like edges in a region; :func:`road_near` from the edges around an object (within twice its extent, on no
object), the road where that object stands. Two users: the photo appearance fills a removed car's hole along the
road's lines (:func:`sdn3d.editing.photo.road.removal_vanishing_point`), and the test-time fit pulls each car
towards the road's axis where it stands (:func:`road_axes`, :attr:`sdn3d.geometric.fit.FitSettings.lane_reg` and
``proposal_lane_reg``).
"""

from __future__ import annotations

import math

import numpy as np
import torch
from torch import Tensor

from sdn3d.image_ops import any_along, any_set, count_set, dilate_square, luminance, nonzero_yx

__all__ = ["image_vanishing_point", "road_near", "road_axes", "axis_yaw", "FORWARD_SNAP_DEG", "VOTE_COHERENCE",
           "VOTE_WINDOW", "VOTE_SPREAD_DEG", "VOTE_REACH_SPREADS"]

#: :func:`road_near`: a voted heading within this many degrees of the camera's forward one is the forward one (a
#: level camera looking down the road; a degree's difference is noise in the edges' directions, and a vanishing point
#: a degree off bends every filled lane line).
FORWARD_SNAP_DEG = 1.0
#: :func:`image_vanishing_point`: an edge pixel votes only where the luma gradients in the ``VOTE_WINDOW`` pixels
#: square around it share one direction to this degree (the structure tensor's coherence, 0-1): lane lines, kerbs,
#: a verge's edge; not the grain of grass, foliage or gravel, whose strong gradients point every way. On the real
#: frame's black-car delete the verge's grass gave most of the strongest edges, and their vote put the road 66
#: degrees off, where its camera's 30 degrees are (docs/results/2026-11-29_cpu/session9/lead/).
VOTE_COHERENCE = 0.9
VOTE_WINDOW = 7
#: :func:`image_vanishing_point`: each edge's line votes for the heading where it meets the horizon, spread by a
#: Gaussian of this many degrees (the direction of a 3x3 Sobel gradient is good to about a degree on a clean edge).
VOTE_SPREAD_DEG = 1.0


def image_vanishing_point(image: Tensor, region: Tensor, K: Tensor, min_edges: int = 50, max_edges: int = 4000,
                          coherence: float = VOTE_COHERENCE, window: int = VOTE_WINDOW,
                          spread_deg: float = VOTE_SPREAD_DEG,
                          forward_snap_deg: float = 0.0) -> tuple[float, float] | None:
    """``(u, v)`` the point on the horizon row ``v = K[1, 2]`` (a level camera's: where every direction of the road
    plane vanishes) that the picture's edges inside ``region (H, W)`` point at: each pixel with a strong luma
    gradient whose neighbourhood's gradients share its direction (structure tensor coherence at least
    ``coherence`` over a ``window``-pixel square: a line, not texture) votes for the heading where its edge's line
    meets the horizon row, spread by a Gaussian of ``spread_deg`` degrees and weighted by the gradient's magnitude
    (a horizontal edge meets it nowhere and does not vote); candidates every half degree of heading within 70
    degrees of the camera's forward; the ``max_edges`` strongest edges vote. None with fewer than ``min_edges`` such
    edge pixels. Lane markings, kerbs and verges below the horizon are such edges: the road's own direction,
    whatever the fitted pose of the removed car says. A winning heading within ``forward_snap_deg`` degrees of the
    camera's forward one is the forward one.

    Example (three lane lines meeting 30 degrees to the right of a 64x128 picture's forward heading):

    >>> import math
    >>> K = torch.tensor([[100.0, 0.0, 63.5], [0.0, 100.0, 20.0], [0.0, 0.0, 1.0]])
    >>> ys, xs = torch.meshgrid(torch.arange(64.0), torch.arange(128.0), indexing="ij")
    >>> u = 63.5 + 100 * math.tan(math.radians(30))
    >>> lines = (ys > 22) & torch.stack([(xs - u - k * (ys - 20)).abs() <= 1.5 for k in (-1.6, 0.0, 1.6)]).any(0)
    >>> image = torch.where(lines, 0.95, 0.4).expand(3, 64, 128)
    >>> found = image_vanishing_point(image, torch.ones(64, 128, dtype=torch.bool), K)
    >>> round(math.degrees(math.atan((found[0] - 63.5) / 100)))
    30
    """
    import cv2

    fx, cx, cy = float(K[0, 0]), float(K[0, 2]), float(K[1, 2])
    y0, y1, x0, x1 = (_sobel_window(region, 1 + window // 2) if any_set(region)
                      else (0, region.shape[0], 0, region.shape[1]))
    crop = image[:, y0:y1, x0:x1]
    y = np.ascontiguousarray(luminance(crop.permute(1, 2, 0).reshape(-1, 3)).view(crop.shape[1:]).float().numpy())
    gx = torch.from_numpy(cv2.Sobel(y, cv2.CV_32F, 1, 0, ksize=3))
    gy = torch.from_numpy(cv2.Sobel(y, cv2.CV_32F, 0, 1, ksize=3))
    mag = (gx**2 + gy**2).sqrt()
    rows = torch.arange(y0, y1)[:, None] > cy + 2  # below the horizon: the road's side
    use = region[y0:y1, x0:x1] & rows & (mag > 0.15)
    if count_set(use) < min_edges:
        return None
    use &= _coherence(gx, gy, window) >= coherence
    if count_set(use) < min_edges:
        return None
    ys, xs = nonzero_yx(use)  # in the window; the vote below reads the picture's coordinates
    m = mag[ys, xs]
    if len(m) > max_edges:  # the strongest ones: the vote's cost stays bounded
        keep = m.topk(max_edges).indices
        ys, xs, m = ys[keep], xs[keep], m[keep]
    tx, ty = -gy[ys, xs] / m, gx[ys, xs] / m  # along the edge
    ys, xs = ys + y0, xs + x0
    heading = torch.deg2rad(torch.arange(-70.0, 70.25, 0.5))
    us = cx + fx * torch.tan(heading)  # (C,)
    slanted = ty.abs() > 1e-3  # a horizontal edge's line never meets the horizon
    meets = xs.float() + (cy - ys.float()) * tx / torch.where(slanted, ty, torch.ones_like(ty))  # its column there
    aim = torch.atan((meets - cx) / fx)  # (N,) the heading it votes for
    spread = math.radians(spread_deg)
    score = (_heading_votes(heading, aim, spread) * (m * slanted)[:, None]).sum(0)
    best = int(score.argmax())
    if abs(float(heading[best])) <= math.radians(forward_snap_deg) + 1e-9:  # the camera looks down the road
        best = int(heading.abs().argmin())
    return float(us[best]), cy


#: :func:`_heading_votes`: a heading this many spreads from an edge's aim gets exactly 0 (``exp(-0.5 * 15^2)`` is
#: under half the smallest float32 subnormal; 14.5 spreads already is).
VOTE_REACH_SPREADS = 15.0


def _heading_votes(heading: Tensor, aim: Tensor, spread: float) -> Tensor:
    """``(N, C)`` float32 ``exp(-0.5 * ((heading[None] - aim[:, None]) / spread) ** 2)`` for ``heading (C,)``
    (increasing, evenly spaced) and ``aim (N,)``: the vanishing-point vote's Gaussians, bit for bit as that one
    expression, with the exponentials taken only within :data:`VOTE_REACH_SPREADS` spreads of each aim (the rest are
    exactly 0). torch's vectorised ``exp`` leaves its fast path for every argument whose result is subnormal or zero
    (40-60 ns each): on the 4000 edges x 281 headings of a removal at 1242x375, nearly all of them, 25-35 ms. Each
    entry is the same arithmetic on the same two numbers (``exp`` gives the same bits at any position of a tensor:
    tests/test_photo_cost.py), so the picture's sums over it are unchanged. Aims that are not finite: the whole
    expression."""
    if len(heading) < 2 or not len(aim) or not bool(torch.isfinite(aim).all()):
        return torch.exp(-0.5 * ((heading[None] - aim[:, None]) / spread).square())
    reach = VOTE_REACH_SPREADS * spread
    step = float(heading[1] - heading[0])
    width = min(int(math.ceil(2 * reach / step)) + 2, len(heading))
    first = torch.searchsorted(heading, aim - reach)  # the first heading within reach of each aim
    at = (first[:, None] + torch.arange(width)[None]).clamp_(max=len(heading) - 1)  # (N, width), repeats at the end
    near = -0.5 * ((heading[at] - aim[:, None]) / spread).square()
    return torch.zeros(len(aim), len(heading), dtype=near.dtype).scatter_(1, at, torch.exp(near))


def _coherence(gx: Tensor, gy: Tensor, window: int) -> Tensor:
    """``(H, W)`` the coherence ``((Jxx - Jyy)^2 + 4 Jxy^2) / (Jxx + Jyy)^2`` (0: gradients every way, 1: one
    direction) of the structure tensor of gradients ``gx, gy (H, W)`` summed over a ``window``-pixel square (zero
    padded): OpenCV's box sums, a tenth of ``avg_pool2d``'s cost (its 49 additions per pixel were 35 ms of a rotate
    edit at 1242x375); equal within float32 rounding, and on the vote's windows (:func:`_sobel_window`) the same bits
    as on the whole picture (test)."""
    import cv2

    jxx, jyy, jxy = (torch.from_numpy(cv2.boxFilter(np.ascontiguousarray(c.numpy()), -1, (window, window),
                                                    normalize=False, borderType=cv2.BORDER_CONSTANT))
                     for c in (gx * gx, gy * gy, gx * gy))
    return ((jxx - jyy).square() + 4 * jxy.square()) / (jxx + jyy).square().clamp(min=1e-12)


def _sobel_window(region: Tensor, margin: int = 1) -> tuple[int, int, int, int]:
    """``(y0, y1, x0, x1)`` of the picture whose Sobel gradients at the ``region (H, W)`` pixels, and within
    ``margin - 1`` pixels of them, equal the whole picture's bit for bit: the region's box grown by ``margin`` pixels
    (a pixel for the 3x3 kernel), its left edge on a multiple of 64 columns and 64 spare columns on the right
    (OpenCV's vector lanes fall on the same pixels, as in :func:`~sdn3d.editing.photo.transfer._blur_window`); the
    picture's edge where it is near."""
    height, width = region.shape
    rows, cols = any_along(region, 1).nonzero().flatten(), any_along(region, 0).nonzero().flatten()
    y0, y1 = max(int(rows[0]) - margin, 0), min(int(rows[-1]) + 1 + margin, height)
    x0 = max(int(cols[0]) - margin, 0) // 64 * 64
    x1 = min(int(cols[-1]) + 1 + margin + 64, width)
    return y0, y1, x0, x1


def road_near(image: Tensor, K: Tensor, mask: Tensor, objects_px: Tensor) -> tuple[float, float] | None:
    """``(u, v)`` the vanishing point of the road around ``mask (H, W)`` (an object's pixels):
    :func:`image_vanishing_point` of the edges within twice the object's extent (at least 20 px) that lie on no object
    of ``objects_px (H, W)``
    (grown by 2 px: a car's own outline is no road line), snapped to the camera's forward heading within
    :data:`FORWARD_SNAP_DEG`; None for an empty mask or where too few edges vote."""
    if not any_set(mask):
        return None
    ys, xs = nonzero_yx(mask)
    extent = max(int(ys.max() - ys.min()), int(xs.max() - xs.min()))
    region = dilate_square(mask, max(2 * extent, 20)) & ~dilate_square(objects_px | mask, 2)
    return image_vanishing_point(image, region, K, forward_snap_deg=FORWARD_SNAP_DEG)


def axis_yaw(u: float, K: Tensor) -> float:
    """The yaw ``ry`` (KITTI convention: a car's long axis is ``(cos ry, 0, -sin ry)`` in the camera frame) of a car
    whose axis runs to the vanishing point at column ``u`` of a level camera ``K (3, 3)``, its front away from the
    camera: the heading ``h = atan((u - cx) / fx)`` right of the camera's forward one is ``ry = h - pi / 2`` (a car
    driving straight ahead: ``-pi / 2``).

    >>> K = torch.tensor([[100.0, 0.0, 50.0], [0.0, 100.0, 20.0], [0.0, 0.0, 1.0]])
    >>> round(math.degrees(axis_yaw(50.0, K))), round(math.degrees(axis_yaw(150.0, K)))
    (-90, -45)
    """
    return math.atan((u - float(K[0, 2])) / float(K[0, 0])) - math.pi / 2


def road_axes(image: Tensor, K: Tensor, masks: Tensor, objects_px: Tensor | None = None) -> Tensor:
    """``(N,)`` float32 the road's axis where each of the objects ``masks (N, H, W)`` stands, as a yaw
    (:func:`axis_yaw` of :func:`road_near`; either end: the axis is the yaw mod pi), NaN where the edges around an
    object do not tell; ``image (3, H, W)`` in [0, 1], ``K (3, 3)`` its level camera, ``objects_px (H, W)`` the
    pixels of every object, whose edges do not vote (None: the masks' union)."""
    if objects_px is None:
        objects_px = masks.any(0) if len(masks) else torch.zeros(image.shape[-2:], dtype=torch.bool)
    axes = torch.full((len(masks),), math.nan)
    for i in range(len(masks)):  # one vote per object, each over its own region
        found = road_near(image, K, masks[i], objects_px)
        if found is not None:
            axes[i] = axis_yaw(found[0], K)
    return axes
