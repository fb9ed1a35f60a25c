"""Image-space operations shared by the datasets and the inference path.

One box convention everywhere in the library: ``(x0, y0, x1, y1)`` in pixels, half-open (pixel ``i``
covers ``[i, i + 1)``; a one-pixel mask at column 3 is ``x0 = 3, x1 = 4``). Two format edges keep
their own convention and convert here: the KITTI / Virtual KITTI annotation box
(:attr:`sdn3d.data.records.ObjectAnnotation.box2d`, ``(l, t, r, b)`` pixel centres, inclusive), which is
also the form the geometric branch's box encoding and crop windows are defined on
(:func:`pixel_centre_boxes` converts), and the editing benchmark's ``roi`` ``[top, left, bottom, right]``
(:mod:`sdn3d.data.edit_benchmark`).

- sizes and resizing: :func:`check_size`, :func:`to_image_tensor`, :func:`resize_image`,
  :func:`resize_map`, :func:`scale_boxes`;
- boxes and centres: :func:`mask_boxes`, :func:`mask_centroids`, :func:`pixel_centre_boxes`;
- label maps: :func:`instance_label_map`, :func:`boundary_map`;
- square object crops of the geometric branch: :func:`square_crop_window`, :func:`crop_windows`,
  :func:`crop_intrinsics` (the datasets and :func:`sdn3d.derender.derender` use the same code, so the
  branch sees identical crops in training and at inference); :class:`InputPhoto`: the photo a working image was
  made from, at its own resolution, and its windows (:meth:`InputPhoto.crops`: the same crops read from it).

Example:
    >>> mask = torch.zeros(1, 4, 6, dtype=torch.bool)
    >>> mask[0, 1:3, 2:5] = True
    >>> mask_boxes(mask).tolist(), pixel_centre_boxes(mask_boxes(mask)).tolist()
    ([[2, 1, 5, 3]], [[2.0, 1.0, 4.0, 2.0]])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.math3d.camera import Intrinsics

__all__ = [
    "luminance",
    "any_set",
    "any_along",
    "count_set",
    "flat_nonzero",
    "nonzero_yx",
    "mask_centroids",
    "check_size",
    "dilate_square",
    "dilate_cross",
    "isin_ids",
    "ids_present",
    "id_counts",
    "to_image_tensor",
    "resize_image",
    "resize_map",
    "scale_boxes",
    "mask_boxes",
    "pixel_centre_boxes",
    "instance_label_map",
    "boundary_map",
    "square_crop_window",
    "crop_windows",
    "crop_intrinsics",
    "InputPhoto",
]


def check_size(size: tuple[int, int], name: str = "size") -> tuple[int, int]:
    """``size`` as two positive ints ``(W, H)``; a ``ValueError`` naming ``name`` otherwise."""
    if len(tuple(size)) != 2 or any(int(s) != s or s <= 0 for s in size):
        raise ValueError(f"{name} must be two positive integers (W, H), got {size!r}")
    return int(size[0]), int(size[1])


def to_image_tensor(rgb: np.ndarray) -> Tensor:
    """``(H, W, 3)`` uint8 -> ``(3, H, W)`` float32 in [0, 1]."""
    if rgb.ndim != 3 or rgb.shape[-1] != 3:
        raise ValueError(f"rgb must have shape (H, W, 3), got {rgb.shape}")
    return torch.from_numpy(np.ascontiguousarray(rgb)).permute(2, 0, 1).float().div_(255.0)


def resize_image(image: Tensor, size: tuple[int, int]) -> Tensor:
    """Resize a ``(C, H, W)`` float image to ``size = (W, H)`` (area when shrinking, else bilinear)."""
    width, height = check_size(size)
    if image.dim() != 3 or not image.is_floating_point():
        raise ValueError(f"image must be a float (C, H, W) tensor, got {image.dtype} {tuple(image.shape)}")
    if tuple(image.shape[-2:]) == (height, width):
        return image
    if height <= image.shape[-2] and width <= image.shape[-1]:
        return F.interpolate(image[None], size=(height, width), mode="area")[0]
    # Bilinear weights are convex, so values stay in the input range.
    return F.interpolate(image[None], size=(height, width), mode="bilinear", align_corners=False)[0]


def resize_map(values: Tensor, size: tuple[int, int]) -> Tensor:
    """Resize a ``(H, W)`` label / instance / depth map to ``size = (W, H)`` with nearest-exact."""
    width, height = check_size(size)
    if values.dim() != 2:
        raise ValueError(f"values must have shape (H, W), got {tuple(values.shape)}")
    if tuple(values.shape) == (height, width):
        return values
    if values.is_floating_point():
        return F.interpolate(values[None, None], size=(height, width), mode="nearest-exact")[0, 0]
    # Integer ids go through float64, which represents every id below 2**53 exactly.
    out = F.interpolate(values[None, None].double(), size=(height, width), mode="nearest-exact")
    return out[0, 0].to(values.dtype)


def scale_boxes(boxes: Tensor, source: Intrinsics, target_size: tuple[int, int]) -> Tensor:
    """Map ``(..., 4)`` pixel-centre boxes ``(l, t, r, b)`` (annotation form) from ``source``'s size to
    ``target_size = (W, H)``.

    Box coordinates are treated as points under the pixel-centre convention
    (``u' = (u + 0.5) sx - 0.5``), the same map :meth:`Intrinsics.resized` applies to the
    principal point, so a projected point inside the box stays inside after resizing.
    """
    width, height = check_size(target_size, "target_size")
    if boxes.shape[-1] != 4:
        raise ValueError(f"boxes must have a last dimension of 4 (l, t, r, b), got {tuple(boxes.shape)}")
    sx, sy = width / source.width, height / source.height
    scale = boxes.new_tensor([sx, sy, sx, sy])
    return (boxes + 0.5) * scale - 0.5


def mask_boxes(masks: Tensor) -> Tensor:
    """``(N, 4)`` int64 boxes ``(x0, y0, x1, y1)`` (half-open) of ``masks (N, H, W)``; an empty mask: all 0."""
    if masks.dim() != 3:
        raise ValueError(f"masks must be (N, H, W), got {tuple(masks.shape)}")
    masks = masks.bool()
    h, w = masks.shape[-2:]
    cols, rows = any_along(masks, 1), any_along(masks, 2)  # (N, W), (N, H)
    xs = torch.arange(w, device=masks.device)
    ys = torch.arange(h, device=masks.device)
    big = max(h, w) + 1
    x0 = torch.where(cols, xs, big).amin(1)
    x1 = torch.where(cols, xs, -1).amax(1) + 1
    y0 = torch.where(rows, ys, big).amin(1)
    y1 = torch.where(rows, ys, -1).amax(1) + 1
    box = torch.stack([x0, y0, x1, y1], 1)
    return torch.where(cols.any(1, keepdim=True), box, torch.zeros_like(box))


def padded_window(rows: Tensor, cols: Tensor, pad: int, size: tuple[int, int]) -> tuple[int, int, int, int]:
    """``(y0, y1, x0, x1)`` (half-open) of the box from the first to the last of the sorted ``rows`` and ``cols``
    (a mask's occupied rows and columns, e.g. ``any_along(mask, 1).nonzero().flatten()``) grown by ``pad`` pixels on
    every side and clipped to a picture of ``size = (H, W)``.

    >>> padded_window(torch.tensor([3, 5]), torch.tensor([0, 9]), 2, (7, 10))
    (1, 7, 0, 10)
    """
    height, width = size
    return (max(int(rows[0]) - pad, 0), min(int(rows[-1]) + 1 + pad, height),
            max(int(cols[0]) - pad, 0), min(int(cols[-1]) + 1 + pad, width))


def mask_centroids(masks: Tensor) -> Tensor:
    """``(N, 2)`` float64 ``(u, v)`` centroid of each of ``masks (N, H, W)`` in pixel-centre coordinates (pixel ``i``
    is at ``i``); an empty mask: ``(0, 0)``.

    Each is the mean column of its mask's pixels and the mean row, from its per-column and per-row counts (exact in
    float64: the sums are integers under 2**53), counted by NumPy for a bool CPU mask (weighing the whole picture by
    a coordinate grid took about 0.1 s for ten 1242x375 masks, the counts about 10 ms).

    Example:
        >>> mask = torch.zeros(2, 4, 6, dtype=torch.bool)
        >>> mask[0, 1:3, 2:5] = True
        >>> mask_centroids(mask).tolist()
        [[3.0, 1.5], [0.0, 0.0]]
    """
    if masks.dim() != 3:
        raise ValueError(f"masks must be (N, H, W), got {tuple(masks.shape)}")
    h, w = masks.shape[-2:]
    if masks.dtype == torch.bool and masks.device.type == "cpu":
        m = masks.numpy()
        cols = torch.from_numpy(np.count_nonzero(m, axis=1).astype(np.float64))  # (N, W)
        rows = torch.from_numpy(np.count_nonzero(m, axis=2).astype(np.float64))  # (N, H)
    else:
        cols = (masks != 0).sum(1, dtype=torch.float64)
        rows = (masks != 0).sum(2, dtype=torch.float64)
    area = cols.sum(1)
    u = cols @ torch.arange(w, dtype=torch.float64, device=cols.device)
    v = rows @ torch.arange(h, dtype=torch.float64, device=rows.device)
    return torch.stack([u, v], 1) / area.clamp(min=1)[:, None]


def pixel_centre_boxes(boxes: Tensor) -> Tensor:
    """``(..., 4)`` half-open ``(x0, y0, x1, y1)`` -> float ``(l, t, r, b)`` pixel centres, inclusive (the
    annotation files' and the geometric branch's form): ``(x0, y0, x1 - 1, y1 - 1)``."""
    if boxes.shape[-1] != 4:
        raise ValueError(f"boxes must have a last dimension of 4, got {tuple(boxes.shape)}")
    return (boxes - boxes.new_tensor([0, 0, 1, 1])).float()


def instance_label_map(semantic: Tensor, instances: Tensor) -> tuple[Tensor, Tensor]:
    """``(label, L)`` from ``(H, W)`` semantic and instance maps (instance wins conflicts).

    Returns:
        label: ``(H, W)`` semantic classes with instance pixels set to ``id // 1000``.
        L: ``(H, W)`` instance id on instance pixels, semantic class elsewhere.
    """
    if semantic.shape != instances.shape:
        raise ValueError(f"semantic and instances must share one shape, got {tuple(semantic.shape)} "
                         f"and {tuple(instances.shape)}")
    is_instance = instances != 0
    label = torch.where(is_instance, instances // INSTANCE_DIVISOR, semantic)
    return label, torch.where(is_instance, instances, label)


def boundary_map(L: Tensor) -> Tensor:
    """pix2pixHD instance boundaries of label maps ``L (B, H, W)``: ``(B, 1, H, W)`` float, 1 where a pixel
    differs from a 4-neighbour (one image: ``boundary_map(L[None])[0]`` is ``(1, H, W)``)."""
    if L.dim() != 3:
        raise ValueError(f"L must be (B, H, W), got {tuple(L.shape)}")
    edge = torch.zeros_like(L, dtype=torch.bool)
    dx = L[:, :, 1:] != L[:, :, :-1]
    dy = L[:, 1:, :] != L[:, :-1, :]
    edge[:, :, 1:] |= dx
    edge[:, :, :-1] |= dx
    edge[:, 1:, :] |= dy
    edge[:, :-1, :] |= dy
    return edge[:, None].float()


def square_crop_window(box: Tensor, margin: float) -> tuple[int, int, int]:
    """Square window ``(left, top, side)`` in whole pixels around a ``(4,)`` box ``(l, t, r, b)``.

    Box coordinates are pixel centres, so the box spans ``r - l + 1`` pixels; the side is
    ``ceil((1 + 2 margin) * max(r - l + 1, b - t + 1))``, centred on the box centre.
    ``left``/``top`` are the indices of the window's first column/row (may be outside the image).
    """
    if margin < 0:
        raise ValueError(f"margin must be non-negative, got {margin}")
    l, t, r, b = (float(v) for v in box)
    side = max(1, math.ceil((1.0 + 2.0 * margin) * max(r - l + 1.0, b - t + 1.0) - 1e-6))
    left = math.floor((l + r) / 2.0 - (side - 1) / 2.0 + 0.5)
    top = math.floor((t + b) / 2.0 - (side - 1) / 2.0 + 0.5)
    return left, top, side




def crop_windows(maps: Tensor, windows: Tensor, size: int, mode: str, antialias: bool = False) -> Tensor:
    """Resample ``N`` windows of ``maps`` to ``(N, C, size, size)`` with ``grid_sample``.

    Output pixel ``j`` of window ``(left, top, side)`` samples ``u = left + (j + 0.5) side / size - 0.5`` (zeros
    outside); a window ``(left, top, width, height)`` (floats allowed) uses ``width`` across and ``height`` down.

    Args:
        maps: ``(C, H, W)`` shared by all windows, or ``(N, C, H, W)`` one per window.
        windows: ``(N, 3)`` ``(left, top, side)`` or ``(N, 4)`` ``(left, top, width, height)`` in pixels.
        mode: ``'bilinear'`` or ``'nearest'``.
        antialias: each output pixel is the mean of ``k x k`` samples spread over its footprint, ``k`` the
            window's ``ceil(side / size)`` (a box filter where the window is larger than the crop; a window at most
            ``size`` across is sampled as without it). Windows of one ``k`` share one ``grid_sample``.
    """
    if windows.dim() != 2 or windows.shape[1] not in (3, 4):
        raise ValueError(f"windows must be (N, 3) (left, top, side) or (N, 4) (left, top, width, height), got "
                         f"{tuple(windows.shape)}")
    n = windows.shape[0]
    if maps.dim() == 3:
        maps = maps[None].expand(n, *maps.shape)
    if maps.dim() != 4 or maps.shape[0] != n:
        raise ValueError(f"maps must be (C, H, W) or (N={n}, C, H, W), got {tuple(maps.shape)}")
    w = windows.to(device=maps.device, dtype=torch.float32)
    if w.shape[1] == 3:
        w = torch.cat([w, w[:, 2:3]], 1)
    if not antialias:
        return _sample_windows(maps, w, size, mode)
    factor = torch.ceil(w[:, 2:].amax(1) / size - 1e-6).clamp_min(1).long()
    out = maps.new_zeros(n, maps.shape[1], size, size, dtype=torch.float32)
    for k in factor.unique().tolist():  # one grid_sample per supersampling factor (a few at most)
        rows = (factor == k).nonzero().flatten()
        fine = _sample_windows(maps[rows], w[rows], size * k, mode)
        out[rows] = fine if k == 1 else F.avg_pool2d(fine, k)
    return out


def _sample_windows(maps: Tensor, w: Tensor, size: int, mode: str) -> Tensor:
    """``crop_windows`` of ``maps (N, C, H, W)`` and windows ``w (N, 4)`` ``(left, top, width, height)``."""
    n = w.shape[0]
    height, width = maps.shape[-2:]
    steps = (torch.arange(size, dtype=torch.float32, device=maps.device) + 0.5)[None]
    gx = (w[:, :1] + (steps * (w[:, 2:3] / size) - 0.5)) * (2.0 / width) + (1.0 / width - 1.0)  # (N, S)
    gy = (w[:, 1:2] + (steps * (w[:, 3:4] / size) - 0.5)) * (2.0 / height) + (1.0 / height - 1.0)
    grid = torch.stack([gx[:, None, :].expand(n, size, size), gy[:, :, None].expand(n, size, size)], -1)
    return F.grid_sample(maps.float(), grid, mode=mode, padding_mode="zeros", align_corners=False)


@dataclass(frozen=True)
class InputPhoto:
    """The photo a working image was made from, at its own resolution: the working image is the photo resized by
    ``scale = (sx, sy)`` (working / input per axis) and cropped at ``offset (left, top)`` of the resized image
    (:class:`sdn3d.editing.frame.PixelFrame`'s map; :meth:`~sdn3d.editing.frame.PixelFrame.photo` makes one).

    :func:`sdn3d.derender.derender` reads the geometric branch's object crops from it (:meth:`crops`), so that a
    small object's crop (and the lamp cue that reads it) holds the photo's detail rather than the working image's.

    Attributes:
        image: ``(3, H_in, W_in)`` float in ``[0, 1]``.
        scale: ``(sx, sy)``: working pixels per input pixel.
        offset: ``(left, top)``: the working image's crop in the resized photo, in working pixels.
    """

    image: Tensor
    scale: tuple[float, float]
    offset: tuple[int, int] = (0, 0)

    def __post_init__(self) -> None:
        if self.image.dim() != 3 or self.image.shape[0] != 3 or not self.image.is_floating_point():
            raise ValueError(f"InputPhoto.image must be a float (3, H, W) tensor, got {self.image.dtype} "
                             f"{tuple(self.image.shape)}")
        if len(self.scale) != 2 or not all(math.isfinite(v) and v > 0 for v in self.scale):
            raise ValueError(f"InputPhoto.scale must be two positive numbers, got {self.scale!r}")

    def windows(self, windows: Tensor) -> Tensor:
        """``(N, 4)`` ``(left, top, width, height)`` in the photo's pixels of working-image windows ``(N, 3)``
        ``(left, top, side)``: the same region (window edges map as ``x_in = (x_work + left) / sx``)."""
        w = windows.double()
        (sx, sy), (ox, oy) = self.scale, self.offset
        return torch.stack([(w[:, 0] + ox) / sx, (w[:, 1] + oy) / sy, w[:, 2] / sx, w[:, 2] / sy], 1).float()

    def crops(self, windows: Tensor, size: int) -> Tensor:
        """``(N, 3, size, size)`` crops of the working-image windows ``(N, 3)`` read from the photo, antialiased
        (:func:`crop_windows`): where a window spans more photo pixels than the crop has, a box filter, as an area
        resize of the photo to the working size would average them."""
        return crop_windows(self.image.float(), self.windows(windows), size, "bilinear", antialias=True)


def crop_intrinsics(intr: Intrinsics, windows: Tensor, size: int) -> Tensor:
    """``(N, 4)`` ``(fx, fy, cx, cy)`` of each window resized to ``size`` (``Intrinsics.cropped().resized()``)."""
    w = windows.double()
    scale = size / w[:, 2]
    return torch.stack([intr.fx * scale, intr.fy * scale, (intr.cx - w[:, 0] + 0.5) * scale - 0.5,
                        (intr.cy - w[:, 1] + 0.5) * scale - 0.5], 1).float()


#: :func:`dilate_square` grows a bool mask by a radius above this with running counts (:func:`_grow_along`), whose
#: time does not grow with the radius; OpenCV's dilation, faster for small radii, took 17 ms at a radius of 1000
#: on 1242x375.
DILATE_COUNTS_MIN = 48


def any_set(mask: Tensor) -> bool:
    """``bool(mask.any())``: by NumPy for a bool CPU ``mask`` (torch's ``any`` reduces a bool picture with a scalar
    loop: 0.45 ms at 1242x375, NumPy 0.02 ms), by torch otherwise."""
    if mask.dtype != torch.bool or mask.device.type != "cpu":
        return bool(mask.any())
    return bool(mask.numpy().any())


def any_along(mask: Tensor, dim: int) -> Tensor:
    """``mask.any(dim)`` (bool): by NumPy for a bool CPU ``mask`` (torch took 0.5-0.7 ms on a 1242x375 picture's rows
    or columns, NumPy 0.02 ms), by torch otherwise."""
    if mask.dtype != torch.bool or mask.device.type != "cpu":
        return mask.any(dim)
    return torch.from_numpy(mask.numpy().any(dim))


def count_set(mask: Tensor) -> int:
    """``int(mask.sum())``: how many elements of a bool ``mask`` are set, by NumPy on the CPU (torch's sum of a bool
    1242x375 picture took 0.2 ms, NumPy's ``count_nonzero`` 0.03 ms), by torch otherwise."""
    if mask.dtype != torch.bool or mask.device.type != "cpu":
        return int(mask.sum())
    return int(np.count_nonzero(mask.numpy()))


def flat_nonzero(mask: Tensor) -> Tensor:
    """``mask.reshape(-1).nonzero().flatten()``: the int64 flat indices of the set elements of a bool ``mask`` in
    row-major order, by NumPy on the CPU (2-6 times as fast as torch's on a 1242x375 picture), by torch
    otherwise."""
    if mask.dtype != torch.bool or mask.device.type != "cpu":
        return mask.reshape(-1).nonzero().flatten()
    return torch.from_numpy(np.flatnonzero(mask.numpy()).astype(np.int64, copy=False))


def nonzero_yx(mask: Tensor) -> tuple[Tensor, Tensor]:
    """``mask.nonzero(as_tuple=True)`` of a 2-D bool ``mask``: its set pixels' rows and columns (int64, row-major
    order, each contiguous), from :func:`flat_nonzero` on the CPU (NumPy's own 2-D ``nonzero`` is slower than
    torch's), by torch otherwise."""
    if mask.dim() != 2:
        raise ValueError(f"nonzero_yx: mask must be 2-D, got shape {tuple(mask.shape)}")
    if mask.dtype != torch.bool or mask.device.type != "cpu":
        ys, xs = mask.nonzero(as_tuple=True)
        return ys, xs
    flat = flat_nonzero(mask)
    width = mask.shape[1]
    return flat // width, flat % width


def dilate_square(mask: Tensor, radius: int) -> Tensor:
    """``mask (H, W)`` bool grown by a ``(2 radius + 1)`` square (OpenCV's separable dilation: a max pool's result
    at a fraction of its time; radii above :data:`DILATE_COUNTS_MIN`: the same pixels from running counts of the
    mask's box, one axis after the other)."""
    import cv2

    if radius <= 0:
        return mask
    m = mask.numpy()
    if not m.any():
        return mask
    if radius <= DILATE_COUNTS_MIN or m.dtype != np.bool_:
        kernel = np.ones((2 * radius + 1, 2 * radius + 1), np.uint8)
        return torch.from_numpy(cv2.dilate(m.astype(np.uint8), kernel) > 0)
    height, width = m.shape
    rows, cols = np.flatnonzero(m.any(1)), np.flatnonzero(m.any(0))
    y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
    top, bottom = max(y0 - radius, 0), min(y1 + radius, height)
    left, right = max(x0 - radius, 0), min(x1 + radius, width)
    grown = _grow_along(m[y0:y1, x0:x1], radius, 0, y0 - top, bottom - top)
    out = np.zeros_like(m)
    out[top:bottom, left:right] = _grow_along(grown, radius, 1, x0 - left, right - left)
    return torch.from_numpy(out)


_CROSS = torch.tensor([[0.0, 1.0, 0.0], [1.0, 1.0, 1.0], [0.0, 1.0, 0.0]]).view(1, 1, 3, 3)


def dilate_cross(mask: Tensor, iterations: int = 1) -> Tensor:
    """``(H, W)`` bool ``mask`` dilated ``iterations`` times by the 4-connected cross (pixels within that many
    city-block steps; ``scipy.ndimage.binary_dilation(mask, iterations=n)``'s default); nothing grows in from
    outside the picture.

    >>> m = torch.zeros(3, 3, dtype=torch.bool); m[1, 1] = True
    >>> dilate_cross(m).int().tolist()
    [[0, 1, 0], [1, 1, 1], [0, 1, 0]]
    """
    x = mask[None, None].float()
    for _ in range(iterations):
        x = (F.conv2d(x, _CROSS, padding=1) > 0).float()
    return x[0, 0] > 0


def _grow_along(m: np.ndarray, radius: int, axis: int, offset: int, size: int) -> np.ndarray:
    """``m`` (bool, 2-D) grown by ``radius`` along ``axis`` into ``size`` places of which ``m`` fills those from
    ``offset`` on: a place is set where a set pixel of ``m`` lies within ``radius`` of it (running counts of ``m``,
    differenced over each place's window)."""
    n = m.shape[axis]
    counts = np.zeros((n + 1, m.shape[1]) if axis == 0 else (m.shape[0], n + 1), np.int32)
    np.cumsum(m, axis=axis, dtype=np.int32, out=counts[1:] if axis == 0 else counts[:, 1:])
    place = np.arange(size) - offset  # each place in m's indices
    hi, lo = np.clip(place + radius + 1, 0, n), np.clip(place - radius, 0, n)
    return np.take(counts, hi, axis=axis) > np.take(counts, lo, axis=axis)


#: :func:`isin_ids`, :func:`ids_present` and :func:`id_counts` index a table by id up to this bound (else torch.isin).
ID_TABLE_MAX = 1 << 20


def _id_range(ids: Tensor) -> int | None:
    """The largest of ``ids`` where all are non-negative integers below :data:`ID_TABLE_MAX`, else None."""
    if ids.dtype.is_floating_point or ids.dtype == torch.bool or not ids.numel():
        return None
    lo, hi = torch.aminmax(ids)
    return int(hi) if int(lo) >= 0 and int(hi) < ID_TABLE_MAX else None


def _lookup(table: Tensor, ids: Tensor) -> Tensor:
    """``table[ids.long()]`` for a 1-D ``table`` and non-negative in-range integer ``ids`` (any shape): on the CPU by
    NumPy's indexing, a third of torch's time for a picture's ids (1.7 against 0.5 ms at 1242x375; the same values,
    a gather)."""
    if table.device.type != "cpu" or ids.device.type != "cpu" or table.requires_grad:
        return table[ids.long()]
    return torch.from_numpy(table.numpy()[ids.numpy()])


def isin_ids(ids: Tensor, wanted: Tensor) -> Tensor:
    """``torch.isin(ids, wanted)`` for an id map ``ids`` (instance ids, any shape): a table indexed by id where the
    ids are non-negative and below :data:`ID_TABLE_MAX` (one gather; torch.isin compares every pixel with every
    wanted id), else torch.isin.

    >>> isin_ids(torch.tensor([[0, 3], [7, 3]]), torch.tensor([3, 9])).tolist()
    [[False, True], [False, True]]
    """
    hi = _id_range(ids)
    if hi is None or wanted.dtype.is_floating_point:
        return torch.isin(ids, wanted)
    table = torch.zeros(hi + 1, dtype=torch.bool)
    table[wanted[(wanted >= 0) & (wanted <= hi)].long()] = True
    return _lookup(table, ids)


def ids_present(ids: Tensor, wanted: Tensor) -> Tensor:
    """``torch.isin(wanted, ids)``: which of ``wanted`` occur in the id map ``ids`` (a count per id where the ids
    are non-negative and below :data:`ID_TABLE_MAX`, else torch.isin).

    >>> ids_present(torch.tensor([[0, 3], [7, 3]]), torch.tensor([3, 9, -1, 0])).tolist()
    [True, False, False, True]
    """
    hi = _id_range(ids)
    if hi is None or wanted.dtype.is_floating_point:
        return torch.isin(wanted, ids)
    seen = torch.bincount(ids.reshape(-1).long(), minlength=hi + 1) > 0
    inside = (wanted >= 0) & (wanted <= hi)
    return seen[wanted.long().clamp(0, hi)] & inside


def id_counts(ids: Tensor, wanted: Tensor) -> Tensor:
    """``(K,)`` int64 ``[(ids == w).sum() for w in wanted]``: the pixels of each of ``wanted (K,)`` in the id map
    ``ids`` (one count per id where the ids are non-negative and below :data:`ID_TABLE_MAX`: a pass over the map in
    all, not one per wanted id).

    >>> id_counts(torch.tensor([[0, 3], [7, 3]]), torch.tensor([3, 9, -1, 0])).tolist()
    [2, 0, 0, 1]
    """
    hi = _id_range(ids)
    if hi is None or wanted.dtype.is_floating_point:
        return torch.stack([(ids == w).sum() for w in wanted]) if len(wanted) else torch.zeros(0, dtype=torch.long)
    counts = torch.bincount(ids.reshape(-1).long(), minlength=hi + 1)
    inside = (wanted >= 0) & (wanted <= hi)
    return torch.where(inside, counts[wanted.long().clamp(0, hi)], 0)


def luminance(rgb: Tensor) -> Tensor:
    """``(...,)`` Rec. 709 luminance of ``rgb (..., 3)`` in [0, 1]."""
    return rgb @ rgb.new_tensor([0.2126, 0.7152, 0.0722])
