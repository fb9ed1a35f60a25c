"""Object masks from boxes without a trained segmenter: OpenCV's GrabCut, one box at a time, nearest first.

A person draws a box around each car; :func:`grabcut_masks` turns the boxes into visible masks:

- Each box is segmented inside a context window (the box grown by ``context`` of its size on each side, at least
  ``min_context_px``): pixels outside the box are background for sure, pixels inside probably foreground.
- Boxes are taken nearest first (the lowest bottom edge: on a road, the nearer car stands lower in the picture);
  the masks already found are background for sure for the boxes behind them, so every pixel has one owner and
  each farther object knows what hides it.
- Where a ``prior`` (the semantic branch's vehicle probability, given only when that branch is trusted) is
  confident, it seeds GrabCut: at least ``prior_high`` probably foreground, at most ``prior_low`` probably
  background.
- ``upsample`` > 1 runs GrabCut on the window enlarged that many times (bicubic), its mask brought back by area. Not
  the default: on the 145 cars and vans of a synthetic tuning tree it changed the mean IoU with the true visible
  masks by -0.021 +- 0.021 (twice) and +0.021 +- 0.019 (three times, at nine times the cost), paired.
- The result is the connected component with most pixels, its holes filled (windows are part of a car's
  silhouette), clipped to the box. Where that covers less than ``min_share`` of the box's free pixels (a small or
  low-contrast car: GrabCut's colour models need more pixels than a distant car has), the box's free pixels are
  the mask instead, and :attr:`BoxMasks.from_box` says so.

OpenCV is imported when a mask is made, not with the module.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import torch
from torch import Tensor

__all__ = ["BoxMasks", "grabcut_masks", "refine_with_silhouettes", "nearest_first", "box_at_point", "CLICK_CAR",
           "click_box", "no_vehicle", "CAR_SIZE", "MIN_FIT_IOU"]


class BoxMasks(NamedTuple):
    """:func:`grabcut_masks`' result: ``masks (N, H, W)`` bool and ``from_box (N,)`` bool, true where the mask is
    the box's free pixels because GrabCut found too little in it."""

    masks: Tensor
    from_box: Tensor


def nearest_first(boxes: Tensor) -> Tensor:
    """``(N,)`` order of ``boxes (N, 4)`` from the lowest bottom edge up (ties: the larger box first).

    >>> nearest_first(torch.tensor([[0, 0, 10, 50], [0, 0, 20, 80], [0, 0, 30, 50]])).tolist()
    [1, 2, 0]
    """
    b = boxes.double()
    area = (b[:, 2] - b[:, 0]) * (b[:, 3] - b[:, 1])
    key = b[:, 3] * (1 + area.max().clamp_min(1)) + area  # bottom edge first, area breaks ties
    return torch.argsort(key, descending=True, stable=True)


def _as_uint8(image: Tensor | np.ndarray) -> np.ndarray:
    """``(H, W, 3)`` contiguous uint8 (BGR order does not matter to GrabCut's colour models)."""
    if isinstance(image, Tensor):
        if image.dim() != 3 or image.shape[0] != 3:
            raise ValueError(f"image must be a (3, H, W) tensor, got {tuple(image.shape)}")
        array = image.detach().cpu().float().clamp(0, 1).permute(1, 2, 0).numpy() * 255 + 0.5
        return np.ascontiguousarray(array.astype(np.uint8))
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"image must be (H, W, 3) uint8, got {image.dtype} {image.shape}")
    return np.ascontiguousarray(image)


def _largest_filled(mask: np.ndarray) -> np.ndarray:
    """The largest 8-connected component of ``mask (h, w)`` uint8 {0, 1}, holes filled."""
    import cv2

    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    if count <= 1:
        return np.zeros_like(mask)
    biggest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    part = (labels == biggest).astype(np.uint8)
    contours, _ = cv2.findContours(part, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    filled = np.zeros_like(part)
    cv2.drawContours(filled, contours, -1, 1, thickness=cv2.FILLED)
    return filled


def _grabcut(crop: np.ndarray, seed: np.ndarray, iterations: int, upsample: int) -> np.ndarray:
    """GrabCut of ``crop (h, w, 3)`` uint8 from ``seed (h, w)`` (``cv2.GC_*`` labels), run ``upsample`` times
    larger; ``(h, w)`` uint8 {0, 1} foreground (never where ``seed`` is background for sure)."""
    import cv2

    height, width = seed.shape
    crop, work = np.ascontiguousarray(crop), seed.copy()
    if upsample > 1:
        crop = cv2.resize(crop, None, fx=upsample, fy=upsample, interpolation=cv2.INTER_CUBIC)
        work = cv2.resize(work, None, fx=upsample, fy=upsample, interpolation=cv2.INTER_NEAREST)
    bgd, fgd = np.zeros((1, 65), np.float64), np.zeros((1, 65), np.float64)
    # GrabCut's colour models start from k-means drawing on OpenCV's per-thread generator: back to its initial state
    # (RNG(0) is RNG(0xffffffff), a new thread's), so a mask does not depend on what ran before in this thread (a
    # long-running editor gives sdn3d-edit's masks, box after box).
    cv2.setRNGSeed(0)
    try:
        cv2.grabCut(crop, work, None, bgd, fgd, iterations, cv2.GC_INIT_WITH_MASK)
    except cv2.error:  # one colour everywhere (no background model can be learnt): the seed's probable foreground
        work[work == cv2.GC_PR_BGD] = cv2.GC_PR_FGD
    fg = ((work == cv2.GC_FGD) | (work == cv2.GC_PR_FGD)).astype(np.float32)
    if upsample > 1:
        fg = cv2.resize(fg, (width, height), interpolation=cv2.INTER_AREA)
    return (fg > 0.5).astype(np.uint8) & (seed != cv2.GC_BGD)


def _box_window(box: Tensor, width: int, height: int, context: float,
                min_context_px: int) -> tuple[tuple[int, int, int, int], tuple[int, int, int, int]] | None:
    """``((x0, y0, x1, y1), (wx0, wy0, wx1, wy1))``: ``box`` rounded and clipped to the image, and the window
    GrabCut learns its background from (the box grown by ``context`` of its size, at least ``min_context_px``, on
    each side); None for a box under 2 pixels wide or high."""
    x0, y0, x1, y1 = (int(round(float(v))) for v in box)
    x0, x1 = max(0, min(x0, width)), max(0, min(x1, width))
    y0, y1 = max(0, min(y0, height)), max(0, min(y1, height))
    if x1 - x0 < 2 or y1 - y0 < 2:
        return None
    gx = max(min_context_px, int(context * (x1 - x0)))
    gy = max(min_context_px, int(context * (y1 - y0)))
    return (x0, y0, x1, y1), (max(0, x0 - gx), max(0, y0 - gy), min(width, x1 + gx), min(height, y1 + gy))


def grabcut_masks(image: Tensor | np.ndarray, boxes: Tensor, *, prior: Tensor | None = None, iterations: int = 5,
                  context: float = 0.5, min_context_px: int = 8, prior_high: float = 0.9,
                  prior_low: float = 0.1, min_share: float = 0.3, upsample: int = 1) -> BoxMasks:
    """The visible masks of the objects in ``boxes`` (module doc).

    Args:
        image: ``(3, H, W)`` float in [0, 1], or ``(H, W, 3)`` uint8.
        boxes: ``(N, 4)`` half-open ``(x0, y0, x1, y1)`` pixels of ``image`` (clipped to it; an empty box gets an
            empty mask).
        prior: ``(H, W)`` foreground probability in [0, 1] that may seed the segmentation, or None.
        iterations: GrabCut iterations per box.
        context, min_context_px: the window around each box that GrabCut learns the background from.
        prior_high, prior_low: the prior's thresholds for probable foreground / background.
        min_share: below this share of the box's free pixels, the mask is the box's free pixels.
        upsample: GrabCut's working scale of the window (1: the image's own pixels).
    """
    import cv2

    if isinstance(upsample, bool) or not isinstance(upsample, int) or upsample < 1:
        raise ValueError(f"upsample must be an integer >= 1, got {upsample!r}")
    pixels = _as_uint8(image)
    height, width = pixels.shape[:2]
    if boxes.dim() != 2 or boxes.shape[1] != 4:
        raise ValueError(f"boxes must be (N, 4), got {tuple(boxes.shape)}")
    if prior is not None and tuple(prior.shape) != (height, width):
        raise ValueError(f"prior must be ({height}, {width}), got {tuple(prior.shape)}")
    prior_np = None if prior is None else prior.detach().cpu().float().numpy()
    out = np.zeros((len(boxes), height, width), dtype=bool)
    from_box = np.zeros(len(boxes), dtype=bool)
    taken = np.zeros((height, width), dtype=bool)
    for i in nearest_first(boxes).tolist():  # each box needs the masks of the nearer ones: sequential
        place = _box_window(boxes[i], width, height, context, min_context_px)
        if place is None:
            continue
        (x0, y0, x1, y1), (wx0, wy0, wx1, wy1) = place
        seed = np.full((wy1 - wy0, wx1 - wx0), cv2.GC_BGD, dtype=np.uint8)
        seed[y0 - wy0:y1 - wy0, x0 - wx0:x1 - wx0] = cv2.GC_PR_FGD
        if prior_np is not None:
            window = prior_np[wy0:wy1, wx0:wx1]
            inside = seed == cv2.GC_PR_FGD
            seed[inside & (window <= prior_low)] = cv2.GC_PR_BGD
        seed[taken[wy0:wy1, wx0:wx1]] = cv2.GC_BGD
        if not (seed == cv2.GC_PR_FGD).any():
            continue
        fg = _grabcut(pixels[wy0:wy1, wx0:wx1], seed, iterations, upsample)
        if prior_np is not None:  # a confident prior keeps its pixels inside the box
            confident = (prior_np[wy0:wy1, wx0:wx1] >= prior_high) & (seed != cv2.GC_BGD)
            fg |= confident.astype(np.uint8)
        fg = _largest_filled(fg).astype(bool)
        box = np.zeros_like(fg)
        box[y0 - wy0:y1 - wy0, x0 - wx0:x1 - wx0] = True
        free = box & ~taken[wy0:wy1, wx0:wx1]
        fg &= free
        if fg.sum() < min_share * free.sum():
            fg, from_box[i] = free, True
        out[i, wy0:wy1, wx0:wx1] = fg
        taken[wy0:wy1, wx0:wx1] |= fg
    return BoxMasks(torch.from_numpy(out), torch.from_numpy(from_box))


#: The car a click implies before GrabCut looks, metres: its height, its longest extent in the picture (a car seen
#: obliquely shows its length and width), the width about the click taken as probably the car's (a car seen from
#: behind), and the height above the road at which a click on its body is taken to be.
CLICK_CAR = {"height": 1.6, "span": 4.6, "core": 1.8, "click_height": 0.7}


def box_at_point(image: Tensor | np.ndarray, point: tuple[float, float], fx: float, fy: float, cy: float, *,
                 camera_height: float = 1.65, iterations: int = 4) -> Tensor:
    """The box of the object under a click, ``(4,)`` half-open ``(x0, y0, x1, y1)`` float pixels of ``image``.

    No weights: the road plane says how large a car at the click can be, and GrabCut finds it there.

    1. The click ``(u, v)`` is taken to be on a car's body :data:`CLICK_CAR` ``click_height`` above the road
       (``y = camera_height`` in the camera frame: no roll or pitch), so the car is ``z = fy (camera_height -
       click_height) / (v - cy)`` metres away (a click at or above the horizon: 40 m; z kept in [2, 80]). Standing
       on the road there, it fills the rows from ``cy + fy (camera_height - height) / z`` to ``cy + fy
       camera_height / z`` and at most ``span fx / z`` columns.
    2. GrabCut runs in a window of that car's rows (a third more above, a sixth more below) and ``span`` on each
       side of the click: probably the object's in the middle (``core`` wide), probably not around it, a disc
       around the click the object's for sure, the window's edge background for sure.
    3. The box is the bounding box of the found component that holds the click (where GrabCut keeps under 20
       pixels of it: the car-sized middle, the geometry's guess).

    >>> img = torch.full((3, 120, 320), 0.45); img[:, 70:100, 140:200] = torch.tensor([0.8, 0.1, 0.1])[:, None, None]
    >>> box_at_point(img, (170.0, 85.0), 300.0, 300.0, 50.0).tolist()
    [140.0, 70.0, 200.0, 100.0]
    """
    return click_box(image, point, fx, fy, cy, camera_height=camera_height, iterations=iterations)[0]


def click_box(image: Tensor | np.ndarray, point: tuple[float, float], fx: float, fy: float, cy: float, *,
              camera_height: float = 1.65, iterations: int = 4) -> tuple[Tensor, bool]:
    """:func:`box_at_point`'s ``(box, found)``: ``found`` false where GrabCut kept under 20 pixels of the component
    under the click (the box is then the road plane's guess of a car there, not something seen), or where that
    component runs from one side of the search window to the other (the road or scenery: nothing stands out)."""
    import cv2

    pixels = _as_uint8(image)
    height, width = pixels.shape[:2]
    u, v = float(point[0]), float(point[1])
    if not (0 <= u < width and 0 <= v < height):
        raise ValueError(f"the point ({u:.0f}, {v:.0f}) is outside the {width}x{height} image")
    z = fy * (camera_height - CLICK_CAR["click_height"]) / (v - cy) if v > cy + 1 else 40.0
    z = min(max(z, 2.0), 80.0)
    span, car_h = CLICK_CAR["span"] * fx / z, CLICK_CAR["height"] * fy / z
    bottom, top = cy + fy * camera_height / z, cy + fy * (camera_height - CLICK_CAR["height"]) / z
    x0, x1 = max(0, int(u - span)), min(width, int(u + span) + 1)
    y0 = max(0, int(min(top - car_h / 3, v - 2)))
    y1 = min(height, int(max(bottom + car_h / 6, v + 3)))
    seed = np.full((y1 - y0, x1 - x0), cv2.GC_PR_BGD, dtype=np.uint8)
    core = CLICK_CAR["core"] * fx / z / 2
    mx0, mx1 = max(0, int(u - core) - x0), max(0, int(u + core) - x0)
    seed[max(0, int(top) - y0):max(0, int(bottom) - y0 + 1), mx0:mx1 + 1] = cv2.GC_PR_FGD
    border = max(1, int(0.03 * min(x1 - x0, y1 - y0)))
    seed[:border], seed[-border:], seed[:, :border], seed[:, -border:] = (cv2.GC_BGD,) * 4
    cv2.circle(seed, (int(u) - x0, int(v) - y0), max(2, int(0.12 * car_h)), int(cv2.GC_FGD), thickness=-1)
    fg = _grabcut(pixels[y0:y1, x0:x1], seed, iterations, 1)
    thin = max(3, int(0.08 * car_h)) | 1  # an opening cuts the thin strips of road or verge that join the car
    fg = cv2.morphologyEx(fg, cv2.MORPH_OPEN, np.ones((thin, thin), np.uint8)) | (seed == cv2.GC_FGD).astype(np.uint8)
    _, labels = cv2.connectedComponents(fg, connectivity=8)
    mine = labels == labels[int(v) - y0, int(u) - x0]
    if labels[int(v) - y0, int(u) - x0] == 0 or mine.sum() < 20:
        return torch.tensor([max(0.0, u - 0.3 * span), max(0.0, top), min(float(width), u + 0.3 * span),
                             min(float(height), bottom)], dtype=torch.float32), False
    rows, cols = np.nonzero(mine)
    # A component from one side of the window to the other (its sure-background border aside) is the road or the
    # scenery around the click, not an object standing out of it.
    spans = cols.min() <= border + 1 and cols.max() >= (x1 - x0) - border - 2
    return torch.tensor([x0 + cols.min(), y0 + rows.min(), x0 + cols.max() + 1, y0 + rows.max() + 1],
                        dtype=torch.float32), not spans


#: Metres a car's (or van's) picture spans, standing on the road: ``height`` its rows, ``width`` its columns (seen
#: from behind: its width; from the side: its length; a truck's trailer is not a car). Generous on purpose: a box
#: outside these is refused (:func:`no_vehicle`), not warned about.
CAR_SIZE = {"height": (0.9, 3.5), "width": (1.0, 8.0)}
#: The silhouette IoU of a box object's 3D fit under which no car-shaped object matches its mask (:func:`no_vehicle`).
#: Real cars named by a box fit at 0.75-0.95 (``docs/EDITING.md``); a box on trees at 0.00.
MIN_FIT_IOU = 0.25


def no_vehicle(box: Tensor | tuple[float, float, float, float], fx: float, fy: float, cy: float,
               image_size: tuple[int, int], *, camera_height: float = 1.65, found: bool = True,
               fit_iou: float | None = None, fit_missing: str | None = None) -> str | None:
    """Why no vehicle stands in ``box`` (half-open ``(x0, y0, x1, y1)`` pixels of an image of ``image_size (W, H)``
    and the camera ``fx``, ``fy``, ``cy``), or None where nothing says so. Each witness is enough:

    - GrabCut: ``found`` false (it kept nothing under a click), or ``fit_missing`` (its mask was too small to fit:
      the reason, e.g. from the de-render's box record);
    - the road plane: a car stands on the road (``camera_height`` below the camera: no roll or pitch), so the box's
      bottom edge lies below the horizon (row ``cy``), and that row says how far away it stands, ``z = fy
      camera_height / (y1 - cy)``, and so how many metres its columns and rows span; a car spans :data:`CAR_SIZE`
      (a box whose bottom or sides touch the image's edge is cut off there: its size is not checked that way);
    - the fit: ``fit_iou``, the silhouette IoU of the 3D car fitted to the mask, under :data:`MIN_FIT_IOU`.

    >>> no_vehicle((10.0, 5.0, 17.0, 11.0), 725.0, 725.0, 187.0, (1242, 375))  # a 7x6 px box in the sky
    'its bottom edge (row 11) is above the horizon (row 187): nothing standing on the road ends there'
    >>> no_vehicle((170.0, 180.0, 1058.0, 355.0), 725.0, 725.0, 187.0, (1242, 375))  # 888x175 px on the road
    'a car whose bottom is at row 355 stands 7.1 m away, where this box is 8.7 m wide (a car: 1-8 m)'
    >>> no_vehicle((466.0, 203.0, 666.0, 333.0), 725.0, 725.0, 187.0, (1242, 375), fit_iou=0.85) is None
    True
    """
    x0, y0, x1, y1 = (float(c) for c in box)
    width, height = image_size
    why = []
    if not found:
        why.append("GrabCut found no object under the click (nothing there stands out from its surroundings)")
    if fit_missing:
        why.append(f"GrabCut found too little in it ({fit_missing})")
    if y1 <= cy + 0.5:
        why.append(f"its bottom edge (row {y1:.0f}) is above the horizon (row {cy:.0f}): nothing standing on the road "
                   "ends there")
    elif y1 < height - 1:
        z = fy * camera_height / (y1 - cy)
        wide, tall = (x1 - x0) * z / fx, (y1 - y0) * z / fy
        (lo_h, hi_h), (lo_w, hi_w) = CAR_SIZE["height"], CAR_SIZE["width"]
        cut = x0 <= 0 or x1 >= width or y0 <= 0  # a side or the top cut off by the image's edge: only too big counts
        sizes = []
        if wide > hi_w or (wide < lo_w and not cut):
            sizes.append(f"{wide:.1f} m wide (a car: {lo_w:g}-{hi_w:g} m)")
        if tall > hi_h or (tall < lo_h and not cut):
            sizes.append(f"{tall:.1f} m tall (a car: {lo_h:g}-{hi_h:g} m)")
        if sizes:
            why.append(f"a car whose bottom is at row {y1:.0f} stands {z:.1f} m away, where this box is "
                       + " and ".join(sizes))
    if fit_iou is not None and fit_iou < MIN_FIT_IOU:
        why.append(f"no car shape fits what GrabCut found in it (3D fit's silhouette IoU {fit_iou:.2f} < "
                   f"{MIN_FIT_IOU})")
    return "; ".join(why) or None


def refine_with_silhouettes(image: Tensor | np.ndarray, boxes: Tensor, masks: Tensor, silhouettes: Tensor, *,
                            refine: Tensor | None = None, others: Tensor | None = None, iterations: int = 5,
                            context: float = 0.5, min_context_px: int = 8, min_share: float = 0.3) -> Tensor:
    """``(N, H, W)`` bool: ``masks`` segmented again by GrabCut, seeded by each object's fitted 3D silhouette.

    GrabCut alone misses what looks like the road: dark wheels, the lower body over its shadow. A car's fitted 3D
    shape says where they are, so the second GrabCut learns their colours as the car's. Inside the box: the
    silhouette shrunk by one pixel is the object's for sure, the silhouette grown by one pixel and the first mask
    probably the object's, the rest probably not; outside the box, and on the pixels of nearer objects (boxes
    nearest first, as :func:`grabcut_masks`) and of ``others``, nothing is. A row not to ``refine``, or whose second
    mask keeps less than ``min_share`` of its box's free pixels, keeps its first mask.

    Args:
        image: ``(3, H, W)`` float in [0, 1], or ``(H, W, 3)`` uint8.
        boxes: ``(N, 4)`` half-open boxes; masks: ``(N, H, W)`` bool, :func:`grabcut_masks`' masks of them.
        silhouettes: ``(N, H, W)`` bool, each object's fitted 3D shape drawn in ``image``.
        refine: ``(N,)`` bool, the rows to segment again (default: all), e.g. those whose fit matched its mask.
        others: ``(H, W)`` bool pixels of other objects, never taken.
        iterations, context, min_context_px, min_share: as :func:`grabcut_masks`.

    >>> img = torch.full((3, 40, 60), 0.5); img[:, 10:30, 20:40] = 0.9; img[:, 24:30, 20:26] = 0.5  # road-grey wheel
    >>> box = torch.tensor([[20.0, 10.0, 40.0, 30.0]])
    >>> first = grabcut_masks(img, box).masks
    >>> sil = torch.zeros(1, 40, 60, dtype=torch.bool); sil[0, 10:30, 20:40] = True  # the fitted car: the whole box
    >>> int(first[0, 24:30, 20:26].sum()), int(refine_with_silhouettes(img, box, first, sil)[0, 24:30, 20:26].sum())
    (0, 25)
    """
    import cv2

    pixels = _as_uint8(image)
    height, width = pixels.shape[:2]
    n = len(boxes)
    if tuple(masks.shape) != (n, height, width) or tuple(silhouettes.shape) != (n, height, width):
        raise ValueError(f"masks and silhouettes must be ({n}, {height}, {width}), got {tuple(masks.shape)} and "
                         f"{tuple(silhouettes.shape)}")
    first = masks.bool().cpu().numpy()
    drawn = silhouettes.bool().cpu().numpy().astype(np.uint8)
    todo = np.ones(n, bool) if refine is None else refine.bool().cpu().numpy()
    out = first.copy()
    taken = np.zeros((height, width), bool) if others is None else others.bool().cpu().numpy().copy()
    ring = np.ones((3, 3), np.uint8)
    for i in nearest_first(boxes).tolist():
        place = _box_window(boxes[i], width, height, context, min_context_px)
        if todo[i] and place is not None and drawn[i].any():
            (x0, y0, x1, y1), (wx0, wy0, wx1, wy1) = place
            window = (slice(wy0, wy1), slice(wx0, wx1))
            inner = cv2.erode(drawn[i][window], ring).astype(bool)
            outer = cv2.dilate(drawn[i][window], ring).astype(bool) | first[i][window]
            box = np.zeros((wy1 - wy0, wx1 - wx0), bool)
            box[y0 - wy0:y1 - wy0, x0 - wx0:x1 - wx0] = True
            free = box & ~taken[window]
            seed = np.full(box.shape, cv2.GC_BGD, dtype=np.uint8)
            seed[free] = cv2.GC_PR_BGD
            seed[free & outer] = cv2.GC_PR_FGD
            seed[free & inner] = cv2.GC_FGD
            fg = _largest_filled(_grabcut(pixels[window], seed, iterations, 1)).astype(bool) & free
            if fg.sum() >= min_share * free.sum():
                out[i] = False
                out[i][window] = fg
        out[i] &= ~taken
        taken |= out[i]
    return torch.from_numpy(out)
