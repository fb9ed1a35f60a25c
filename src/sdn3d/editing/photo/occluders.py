"""Thin things in front of a car: a pole, a sign post, a tree trunk that the car's mask leaves out.

A car's fitted template covers such a thing (the template is the whole car), while its mask, which is what the
photo showed of the car, goes round it. Every edit used to treat those pixels as the car's: a delete filled them
(the fitted outline joins the hole) and a move left the road fill there, so the pole vanished. :func:`thin_occluders`
finds them, and :func:`~sdn3d.editing.photo.transfer.render_photo` keeps them in front of whatever the edit draws
behind them (source code ``in front``).

What counts: pixels inside a car's fitted outline that no mask claims, in an upright strip

- with the car's own mask on both sides in its rows (a template that overshoots its car leaves bands along the
  outline's edge, with the car on one side only: those stay the car's, and a delete removes them);
- at most ``max_width`` of the car's outline height wide and at least ``min_height`` of it tall;
- whose colour differs from the car pixels beside it (a strip the mask missed but that looks like the car is the car).

Found strips run on up and down through unclaimed pixels of their own colour (the pole above the roof and below the
sills, where a delete's hole and shadow band reach).
"""

from __future__ import annotations

import numpy as np
import torch
from torch import Tensor

from sdn3d.image_ops import any_along, any_set, flat_nonzero

__all__ = ["thin_occluders"]


def _flanked(mask_ids: Tensor, outline_ids: Tensor, candidate: Tensor, reach: Tensor) -> Tensor:
    """``(H, W)`` bool: the nearest mask pixel to the left and the one to the right of each candidate pixel in its row
    both belong to the car whose outline covers it and lie within ``reach (H, W)`` pixels."""
    width = mask_ids.shape[1]
    cols = torch.arange(width).expand_as(mask_ids)
    def nearest_before(ids: Tensor) -> Tensor:  # column of the last mask pixel at or before each column (-1: none)
        return torch.cummax(torch.where(ids != 0, cols, torch.full_like(cols, -1)), dim=1).values
    before = nearest_before(mask_ids)
    after = width - 1 - nearest_before(mask_ids.flip(1)).flip(1)  # width: none
    def side(at: Tensor) -> Tensor:
        ok = (at >= 0) & (at < width)
        owner = mask_ids.gather(1, at.clamp(0, width - 1))
        return candidate & ok & (owner == outline_ids) & ((at - cols).abs() <= reach)
    return side(before) & side(after)


def thin_occluders(image: Tensor, mask_ids: Tensor, outline_ids: Tensor, max_width: float = 0.3,
                   min_height: float = 0.4, min_contrast: float = 0.08) -> Tensor:
    """``(H, W)`` bool: pixels of thin upright things in front of a car (module doc).

    Args:
        image: ``(3, H, W)`` float in [0, 1], the picture.
        mask_ids: ``(H, W)`` int64 instance id of the mask at each pixel (0: none).
        outline_ids: ``(H, W)`` int64 instance id of the fitted template drawn at each pixel (0: none).
        max_width, min_height: the strip's width at most, and height at least, these shares of its car's outline
            height.
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
    if not any_set(candidate):
        return candidate
    # Everything up to the upright growth lies on the rows the outlines cover (each car's height is its outline's):
    # worked out on that band of rows, then put back in the picture.
    rows_used = any_along(outline_ids != 0, 1).nonzero().flatten()
    y0, y1 = int(rows_used[0]), int(rows_used[-1]) + 1
    found = torch.zeros_like(candidate)
    found[y0:y1] = _strips(image[:, y0:y1], mask_ids[y0:y1], outline_ids[y0:y1], candidate[y0:y1], max_width,
                           min_height, min_contrast)
    return _extend_upright(found, image, mask_ids, min_contrast)


def _components(mask: Tensor) -> tuple[Tensor, int]:
    """``(labels (H, W) int64, count)``: the 4-connected components of ``mask (H, W)`` bool (scipy.ndimage.label's
    default connectivity), numbered ``1..count`` in OpenCV's order, 0 elsewhere. OpenCV, not scipy.ndimage:
    importing that cost every photo edit 0.15-0.2 CPU s (issue 40).

    >>> m = torch.tensor([[1, 1, 0, 0], [0, 0, 1, 0], [1, 0, 1, 1]], dtype=torch.bool)  # diagonal: not connected
    >>> labels, count = _components(m); count, (labels > 0).equal(m), len(labels[m].unique())
    (3, True, 3)
    """
    import cv2

    count, labels = cv2.connectedComponents(mask.numpy().astype(np.uint8), connectivity=4, ltype=cv2.CV_32S)
    return torch.from_numpy(labels.astype(np.int64)), count - 1  # label 0: the background


def _strips(image: Tensor, mask_ids: Tensor, outline_ids: Tensor, candidate: Tensor, max_width: float,
            min_height: float, min_contrast: float) -> Tensor:
    """:func:`thin_occluders` before the upright growth: the strips found among the ``candidate`` pixels."""
    height, width = outline_ids.shape
    # Each car's outline height at each of its pixels (only cars with a candidate pixel: few ids to look up).
    cars = torch.unique(outline_ids[candidate])
    slot = torch.searchsorted(cars, outline_ids).clamp(max=len(cars) - 1)
    slot = torch.where(cars[slot] == outline_ids, slot, torch.full_like(slot, len(cars)))  # len(cars): another car
    rows = torch.arange(height)[:, None].expand_as(outline_ids)
    top = torch.full((len(cars) + 1,), height).scatter_reduce(0, slot.flatten(), rows.flatten(), "amin")
    bottom = torch.full((len(cars) + 1,), -1).scatter_reduce(0, slot.flatten(), rows.flatten(), "amax")
    car_height = (bottom - top + 1).clamp(min=1).float()[slot]
    reach = torch.where(candidate, (max_width * car_height).ceil().long(), torch.zeros_like(outline_ids))
    # Strips are cut from the flanked pixels: the bands where a template overshoots its car (which join a strip at
    # its ends) have the car's mask on one side at most.
    flanked = _flanked(mask_ids, outline_ids, candidate, reach)
    if not any_set(flanked):
        return torch.zeros_like(candidate)
    labels_t, count = _components(flanked)  # what follows is per component: their numbering changes nothing
    pix = flat_nonzero(flanked)  # every statistic below is over these pixels
    lab = labels_t.flatten()[pix]
    size = torch.bincount(lab, minlength=count + 1).float()
    comp_car_height = torch.zeros(count + 1).scatter_reduce(0, lab, car_height.flatten()[pix], "amax")
    def extent(coord: Tensor) -> Tensor:
        lo = torch.full((count + 1,), 1 << 30).scatter_reduce(0, lab, coord, "amin")
        hi = torch.full((count + 1,), -1).scatter_reduce(0, lab, coord, "amax")
        return (hi - lo + 1).float()
    strip_height, strip_width = extent(pix // width), extent(pix % width)
    keep = (strip_height >= min_height * comp_car_height) & (strip_width <= (max_width * comp_car_height).ceil())
    keep[0] = False
    if not any_set(keep):
        return torch.zeros_like(candidate)
    # Colour: the strip against the car's mask pixels just left and right of it.
    pixels = image.reshape(3, -1).T  # (H*W, 3)
    strip = (torch.zeros(count + 1, 3, dtype=torch.float64).index_add_(0, lab, pixels[pix].double())
             / size.clamp(min=1)[:, None])
    side_sum = torch.zeros(count + 1, 3, dtype=torch.float64)
    side_n = torch.zeros(count + 1, dtype=torch.float64)
    for step in (-1, 1):
        beside = pix + step
        ok = (beside % width == (pix % width) + step) & (mask_ids.flatten()[beside.clamp(0, height * width - 1)] != 0)
        side_sum.index_add_(0, lab[ok], pixels[beside[ok]].double())
        side_n.index_add_(0, lab[ok], torch.ones(int(ok.sum()), dtype=torch.float64))
    contrast = (strip - side_sum / side_n.clamp(min=1)[:, None]).abs().mean(1)
    keep &= contrast >= min_contrast
    return keep[labels_t] & flanked


def _extend_upright(found: Tensor, image: Tensor, mask_ids: Tensor, step: float) -> Tensor:
    """``found (H, W)`` grown up and down its columns through pixels no mask claims whose colour is within ``step``
    (mean absolute difference) of the pixel above (below) them: a pole runs on past the car's outline, where a
    delete's hole and its shadow band would otherwise paint it over."""
    if not any_set(found):
        return found
    xs = any_along(found, 0).nonzero().flatten()
    x0, x1 = int(xs.min()), int(xs.max()) + 1
    colours = image[:, :, x0:x1]
    free = mask_ids[:, x0:x1] == 0
    # Vertical runs of free pixels, each row like the one above: a run breaks where that fails.
    joined = ((colours[:, 1:] - colours[:, :-1]).abs().mean(0) < step) & free[1:] & free[:-1]  # (H-1, w)
    run = torch.cat([torch.zeros(1, x1 - x0, dtype=torch.long), (~joined).long().cumsum(0)])  # (H, w) per column
    run = run + torch.arange(x1 - x0)[None, :] * (found.shape[0] + 1)  # unique across columns
    window = found[:, x0:x1]
    hit = torch.zeros(int(run.max()) + 1, dtype=torch.bool)
    hit[run[window]] = True
    grown = hit[run] & (free | window)
    out = found.clone()
    out[:, x0:x1] |= grown
    return out
