"""Thin things in front of a car: a pole, a sign post, a tree trunk that the car's mask leaves out.

A car's fitted template covers such a thing (the template is the whole car), while its mask, which is what the
photo showed of the car, goes round it. Every edit used to treat those pixels as the car's: a delete filled them
(the fitted outline joins the hole) and a move left the road fill there, so the pole vanished. :func:`thin_occluders`
finds them, and :func:`~sdn3d.editing.photo.transfer.render_photo` keeps them in front of whatever the edit draws
behind them (source code ``in front``).

What counts: pixels inside a car's fitted outline that no mask claims, in an upright strip

- with the car's own mask on both sides in most of its rows (a template that overshoots its car leaves bands along
  the outline's edge, with the car on one side only: those stay the car's, and a delete removes them);
- at most ``max_width`` of the car's outline height wide and at least ``min_height`` of it tall;
- whose colour differs from the car pixels beside it (a strip the mask missed but that looks like the car is the car).

Found strips run on up and down through unclaimed pixels of their own colour (the pole above the roof and below the
sills, where a delete's hole and shadow band reach).
"""

from __future__ import annotations

import numpy as np
import torch
from scipy import ndimage
from torch import Tensor

__all__ = ["thin_occluders"]


def _flanked(mask_ids: Tensor, outline_ids: Tensor, candidate: Tensor, reach: Tensor) -> tuple[Tensor, Tensor]:
    """``(left (H, W), right (H, W))`` bool: within ``reach (H, W)`` pixels to the left (right) of each candidate pixel
    in its row lies a mask pixel of the car whose outline covers it."""
    height, width = mask_ids.shape
    left = torch.zeros_like(candidate)
    right = torch.zeros_like(candidate)
    for d in range(1, int(reach.max()) + 1 if candidate.any() else 1):
        near = candidate & (reach >= d)
        shifted = torch.zeros_like(mask_ids)
        shifted[:, d:] = mask_ids[:, :-d]  # the mask d pixels to the left
        left |= near & (shifted == outline_ids)
        shifted = torch.zeros_like(mask_ids)
        shifted[:, :-d] = mask_ids[:, d:]
        right |= near & (shifted == outline_ids)
    return left, right


def thin_occluders(image: Tensor, mask_ids: Tensor, outline_ids: Tensor, max_width: float = 0.3,
                   min_height: float = 0.4, min_flanked: float = 0.6, min_contrast: float = 0.08) -> Tensor:
    """``(H, W)`` bool: pixels of thin upright things in front of a car (module doc).

    Args:
        image: ``(3, H, W)`` float in [0, 1], the picture.
        mask_ids: ``(H, W)`` int64 instance id of the mask at each pixel (0: none).
        outline_ids: ``(H, W)`` int64 instance id of the fitted template drawn at each pixel (0: none).
        max_width, min_height: the strip's width at most, and height at least, these shares of its car's outline
            height.
        min_flanked: share of the strip's pixels with the car's mask on both sides in their row.
        min_contrast: the strip's mean colour differs from the car pixels just beside it by at least this (mean
            absolute difference over the channels).

    Example:
        >>> ids = torch.zeros(20, 30, dtype=torch.long)
        >>> ids[5:15, 5:25] = 7
        >>> outline = ids.clone()
        >>> ids[5:15, 14:16] = 0  # a pole two pixels wide crosses the car
        >>> image = torch.full((3, 20, 30), 0.5)
        >>> image[:, :, 14:16] = 0.1
        >>> thin_occluders(image, ids, outline)[5:15, 14:16].all().item()
        True
    """
    candidate = (outline_ids != 0) & (mask_ids == 0)
    out = torch.zeros_like(candidate)
    if not bool(candidate.any()):
        return out
    # Each car's outline height, at each of its pixels.
    ids, inverse = torch.unique(outline_ids, return_inverse=True)
    rows = torch.arange(outline_ids.shape[0])[:, None].expand_as(outline_ids)
    top = torch.full((len(ids),), outline_ids.shape[0]).scatter_reduce(0, inverse.flatten(), rows.flatten(), "amin")
    bottom = torch.zeros(len(ids), dtype=torch.long).scatter_reduce(0, inverse.flatten(), rows.flatten(), "amax")
    car_height = (bottom - top + 1).float()[inverse]
    reach = torch.where(candidate, (max_width * car_height).ceil().long(), torch.zeros_like(outline_ids))
    left, right = _flanked(mask_ids, outline_ids, candidate, reach)
    labels, count = ndimage.label(candidate.numpy())
    if not count:
        return out
    labels_t = torch.from_numpy(labels.astype(np.int64))
    flat = labels_t.flatten()
    size = torch.bincount(flat, minlength=count + 1).float()
    flanked = torch.bincount(flat, weights=(left & right).flatten().float(), minlength=count + 1)
    height = car_height.flatten()
    comp_car_height = torch.zeros(count + 1).scatter_reduce(0, flat, height, "amax")
    # The car pixels beside the strip: the mask pixels of its car one pixel left or right of it.
    beside = torch.zeros_like(candidate)
    beside[:, 1:] |= candidate[:, :-1]
    beside[:, :-1] |= candidate[:, 1:]
    beside &= mask_ids != 0
    beside_label = torch.zeros_like(flat)
    shifted = torch.zeros_like(labels_t)
    shifted[:, 1:] = labels_t[:, :-1]
    beside_label = torch.where(beside.flatten(), shifted.flatten(), beside_label)
    shifted = torch.zeros_like(labels_t)
    shifted[:, :-1] = labels_t[:, 1:]
    beside_label = torch.where(beside.flatten() & (beside_label == 0), shifted.flatten(), beside_label)
    pixels = image.reshape(3, -1).T.double()  # (H*W, 3)
    def mean_colour(lab: Tensor, weight: Tensor) -> Tensor:
        total = torch.zeros(count + 1, 3, dtype=torch.float64).index_add_(0, lab, pixels * weight[:, None])
        n = torch.zeros(count + 1, dtype=torch.float64).index_add_(0, lab, weight)
        return total / n.clamp(min=1)[:, None]
    strip = mean_colour(flat, candidate.flatten().double())
    side = mean_colour(beside_label, (beside_label > 0).double())
    contrast = (strip - side).abs().mean(1)
    cols = torch.arange(outline_ids.shape[1])[None, :].expand_as(outline_ids).flatten()
    def extent(coord: Tensor) -> Tensor:
        lo = torch.full((count + 1,), 1 << 30).scatter_reduce(0, flat, coord, "amin")
        hi = torch.full((count + 1,), -1).scatter_reduce(0, flat, coord, "amax")
        return (hi - lo + 1).float()
    strip_height, strip_width = extent(rows.flatten()), extent(cols)
    keep = ((flanked >= min_flanked * size) & (strip_height >= min_height * comp_car_height)
            & (strip_width <= (max_width * comp_car_height).ceil()) & (contrast >= min_contrast))
    keep[0] = False
    found = keep[labels_t] & candidate
    return _extend_upright(found, image, mask_ids, int(comp_car_height[keep].max()) if bool(keep.any()) else 0,
                           min_contrast)


def _extend_upright(found: Tensor, image: Tensor, mask_ids: Tensor, limit: int, step: float) -> Tensor:
    """``found (H, W)`` grown up and down, at most ``limit`` rows, through pixels no mask claims whose colour is within
    ``step`` (mean absolute difference) of the pixel above (below) them: a pole runs on past the car's outline, where
    a delete's hole and its shadow band would otherwise paint it over."""
    if limit <= 0 or not bool(found.any()):
        return found
    free = mask_ids == 0
    ys, xs = found.nonzero(as_tuple=True)
    y0, y1 = max(int(ys.min()) - limit, 0), min(int(ys.max()) + limit + 1, found.shape[0])
    x0, x1 = int(xs.min()), int(xs.max()) + 1
    window = found[y0:y1, x0:x1].clone()
    colours = image[:, y0:y1, x0:x1]
    open_ = free[y0:y1, x0:x1]
    close_down = (colours[:, 1:] - colours[:, :-1]).abs().mean(0) < step  # (h-1, w): row r+1 like row r
    for _ in range(limit):
        grown = window.clone()
        grown[1:] |= window[:-1] & close_down & open_[1:]
        grown[:-1] |= window[1:] & close_down & open_[:-1]
        if torch.equal(grown, window):
            break
        window = grown
    out = found.clone()
    out[y0:y1, x0:x1] = window
    return out
