"""Per-pixel fills of a scene's maps, shared by :mod:`sdn3d.scene.maps` and :mod:`sdn3d.editing.apply`.

:func:`scene_code_map` gives each pixel the texture code of its ``L`` value from a scene's object and
background codes (the generator's z-map; :func:`sdn3d.textural.codes.code_map` is the same for the
encoder's :class:`~sdn3d.textural.codes.TextureCodes` rows); :func:`fill_background` relabels the pixels
that moved or deleted objects leave. Neither renders anything.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import Tensor

from sdn3d.labels import IGNORE_INDEX, INSTANCE_DIVISOR

__all__ = ["scene_code_map", "fill_background"]


def scene_code_map(label_map: Tensor, instance_ids: Tensor, codes: Tensor, background_codes: Tensor) -> Tensor:
    """``(C, H, W)`` code of each pixel's ``L`` value (the generator's z-map).

    Args:
        label_map: ``(H, W)`` ``L`` (instance ids >= 1000, classes below; 255 ignore gets zeros).
        instance_ids: ``(N,)`` object ids with ``codes (N, C)``; ids absent from ``L`` are unused,
            object pixels of unknown ids get zeros.
        background_codes: ``(num_classes, C)``.
    """
    num, dim = background_codes.shape
    is_obj = label_map >= INSTANCE_DIVISOR
    # One gather from a table of the background codes, the zero code (row ``num``) and the object codes.
    index = torch.where(~is_obj & (label_map >= 0) & (label_map < num), label_map, num)
    table = [background_codes, background_codes.new_zeros(1, dim)]
    if len(instance_ids):
        order = instance_ids.argsort()
        sorted_ids = instance_ids[order]
        pos = torch.searchsorted(sorted_ids, label_map).clamp(max=len(sorted_ids) - 1)
        index = torch.where(is_obj & (sorted_ids[pos] == label_map), num + 1 + pos, index)
        table.append(codes[order].to(background_codes.dtype))
    # index_select over the flattened map: several times faster on CPU than advanced indexing.
    return torch.cat(table).T.contiguous().index_select(1, index.flatten()).view(dim, *label_map.shape)


def fill_background(semantic: Tensor, vacated: Tensor, thing_classes: Tensor) -> Tensor:
    """Relabel ``vacated`` pixels with background: the label of the nearest *source* pixel.

    Source pixels are those not vacated, not of an instance class (``thing_classes``, so that
    freed regions never grow car-coloured blobs without an instance) and not ignore (255);
    nearest by OpenCV's labelled distance transform (``cv2.distanceTransformWithLabels``, the 5x5 mask's
    Euclidean approximation: a label map needs no exact distances, and importing ``scipy.ndimage`` for
    its exact transform cost every edit call about a second). A car removed from a road thus takes road
    labels below the horizon and the labels of what is beside it above. If no pixel qualifies, the thing/ignore
    exclusions are dropped; if every pixel is vacated, the map is returned unchanged.

    Args:
        semantic: ``(H, W)`` int64 class map.
        vacated: ``(H, W)`` bool.
        thing_classes: ``(T,)`` class ids with instances.
    """
    if semantic.shape != vacated.shape:
        raise ValueError(f"semantic {tuple(semantic.shape)} and vacated {tuple(vacated.shape)} must match")
    if not bool(vacated.any()):
        return semantic.clone()
    sem, vac = semantic.cpu().numpy(), vacated.cpu().numpy().astype(bool)
    source = ~vac & ~np.isin(sem, thing_classes.cpu().numpy()) & (sem != IGNORE_INDEX)
    if not source.any():
        source = ~vac
    if not source.any():
        return semantic.clone()
    import cv2  # the photo appearance imports it anyway

    # Every source pixel is a zero of the input and gets its own label; every other pixel takes the label of its
    # nearest zero, which maps back to that pixel's coordinates.
    _, labels = cv2.distanceTransformWithLabels((~source).astype(np.uint8), cv2.DIST_L2, 5,
                                                labelType=cv2.DIST_LABEL_PIXEL)
    ys, xs = np.nonzero(source)
    where = np.zeros((labels.max() + 1, 2), dtype=np.int64)
    where[labels[ys, xs]] = np.stack([ys, xs], 1)
    ii, jj = where[labels, 0], where[labels, 1]
    out = sem.copy()
    out[vac] = sem[ii[vac], jj[vac]]
    return torch.from_numpy(out).to(semantic.device)
