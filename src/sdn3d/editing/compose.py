"""The edited picture at the input's resolution: the generator's pixels only where the edit changed the scene.

The textural generator re-synthesises the whole frame at the working size, so its picture is blurrier
than the input everywhere and smaller than it. ``compose='edited'`` (the default of ``sdn3d-edit``,
:func:`sdn3d.editing.render.edit_image` and the demo's edit grids) keeps the input and takes from the
generator only the *edit region* (:func:`edit_region_mask`, working size): the source and target
footprints of the edited objects (:func:`edited_object_ids`: added, deleted, or changed in template,
shape, size, pose or code) and every pixel whose generator inputs changed (label, instance, code, pose,
normal, depth, boundary: vacated pixels, the freed pixels an occluded object now covers, recoloured
background), dilated by ``dilate_px``. :func:`compose_edited`
upsamples the generator's picture and a feathered alpha (:func:`feather_alpha`) back through the input
transform (:class:`~sdn3d.editing.frame.PixelFrame`: aspect-preserving scale, then a central crop) and
blends; every pixel outside the feathered region or outside the crop is the input's, bit for bit.
``compose='full'`` is the paper's protocol: the generator's whole picture at the working size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.editing.frame import PixelFrame, sampling_grid
from sdn3d.errors import UserInputError
from sdn3d.scene.code import ObjectTable
from sdn3d.scene.maps import ComposedMaps

__all__ = ["Compose", "COMPOSE_MODES", "ComposeSettings", "ComposeSettingsError", "edited_object_ids", "changed_pixels",
           "edit_region_mask", "feather_alpha", "compose_edited", "compose_edit"]


class Compose(StrEnum):
    """How the generator's picture becomes the edited one (module doc): ``edited``, the input with the edit region
    blended in at its resolution; ``full``, the generator's picture. A ``str`` equal to its value, so records and
    messages that wrote the name write the same."""

    EDITED = "edited"
    FULL = "full"


#: The compose modes' names, in the order messages list them.
COMPOSE_MODES = tuple(c.value for c in Compose)

#: Maps whose float values differ by more than this count as changed (the rasterizer is deterministic:
#: an untouched pixel's values are identical; the tolerance only absorbs float reordering).
CHANGE_TOLERANCE = 1e-5


class ComposeSettingsError(UserInputError):
    """A bad ``compose`` setting (mode, dilation, feathering)."""


@dataclass(frozen=True)
class ComposeSettings:
    """How an edit becomes a picture.

    Attributes:
        mode: :class:`Compose` (its name is accepted and parsed).
        dilate_px: working-size pixels the edit region grows by (seams of the generator's receptive field).
        feather_px: working-size pixels over which the alpha ramps from 0 (region edge) to 1, inside the region.
    """

    mode: Compose = Compose.EDITED
    dilate_px: int = 4
    feather_px: int = 4

    def __post_init__(self) -> None:
        if not isinstance(self.mode, str) or self.mode not in COMPOSE_MODES:
            raise ComposeSettingsError(f"compose must be one of {COMPOSE_MODES}, got {self.mode!r}")
        object.__setattr__(self, "mode", Compose(self.mode))
        for name in ("dilate_px", "feather_px"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 64:
                raise ComposeSettingsError(f"compose_{name} must be an integer in [0, 64], got {value!r}")

    def to_dict(self) -> dict:
        return {"mode": self.mode.value, "dilate_px": self.dilate_px, "feather_px": self.feather_px}


def edited_object_ids(before: ObjectTable, after: ObjectTable) -> Tensor:
    """``(K,)`` int64 sorted ids of objects an edit added, deleted or changed in template, FFD, size, yaw, location
    or code. An object whose mask alone changed (it now covers pixels a deleted or moved object freed) is not
    edited: only those pixels change (:func:`changed_pixels`), the rest of it stays the input's."""
    ids_b, ids_a = before.instance_id.cpu(), after.instance_id.cpu()
    only = torch.cat([ids_b[~torch.isin(ids_b, ids_a)], ids_a[~torch.isin(ids_a, ids_b)]])
    pairs = (ids_b[:, None] == ids_a[None, :]).nonzero()  # (M, 2) rows of the same id in both tables
    rb, ra = pairs[:, 0], pairs[:, 1]
    changed = torch.zeros(len(pairs), dtype=torch.bool)
    for name in ("template_id", "phi", "dims", "ry", "location", "code"):
        vb, va = getattr(before, name).cpu()[rb], getattr(after, name).cpu()[ra]
        diff = vb != va
        changed |= diff.flatten(1).any(1) if diff.dim() > 1 else diff
    return torch.cat([only, ids_b[rb[changed]]]).unique()


def changed_pixels(before: ComposedMaps, after: ComposedMaps) -> Tensor:
    """``(H, W)`` bool: pixels where any generator input differs between the two scenes' maps."""
    changed = torch.zeros(before.instance.shape, dtype=torch.bool, device=before.instance.device)
    for name, a in before.as_dict().items():
        b = getattr(after, name).to(a.device)
        if a.shape != b.shape:
            raise ValueError(f"maps.{name}: shapes {tuple(a.shape)} and {tuple(b.shape)} differ")
        diff = (a - b).abs() > CHANGE_TOLERANCE if a.is_floating_point() else a != b
        changed |= diff if diff.dim() == 2 else diff.any(0)
    return changed


def edit_region_mask(before: ComposedMaps, after: ComposedMaps, edited_ids: Tensor, dilate_px: int = 4) -> Tensor:
    """``(H, W)`` bool edit region at the working size (module doc): the footprints of ``edited_ids (K,)`` in
    both maps, and every changed pixel (:func:`changed_pixels`), dilated by ``dilate_px`` (a square)."""
    ids = edited_ids.to(before.instance.device)
    region = changed_pixels(before, after)
    region |= torch.isin(before.instance, ids) | torch.isin(after.instance.to(ids.device), ids)
    if dilate_px > 0 and bool(region.any()):
        k = 2 * int(dilate_px) + 1
        region = F.max_pool2d(region[None, None].float(), k, stride=1, padding=int(dilate_px))[0, 0] > 0
    return region


def _erode(x: Tensor, open_sides: tuple[bool, bool, bool, bool]) -> Tensor:
    """One 3x3 erosion of ``x (1, 1, h, w)`` in [0, 1]; beyond a side counts as outside the region where
    ``open_sides`` (left, right, top, bottom) says so (a crop edge), else as its edge pixel (the frame edge)."""
    padded = F.pad(x, (1, 1, 1, 1), mode="replicate")
    left, right, top, bottom = open_sides
    if left:
        padded[..., :, 0] = 0
    if right:
        padded[..., :, -1] = 0
    if top:
        padded[..., 0, :] = 0
    if bottom:
        padded[..., -1, :] = 0
    return -F.max_pool2d(-padded, 3, stride=1)


def feather_alpha(region: Tensor, feather_px: int,
                  open_sides: tuple[bool, bool, bool, bool] = (False, False, False, False)) -> Tensor:
    """``(h, w)`` float32 alpha of a ``region (h, w)`` bool: exactly 0 outside it, ``smoothstep(d / F)`` for a
    pixel ``d`` erosions deep (``d = 1`` on the region's edge), 1 from ``F = feather_px`` pixels deep on.
    ``open_sides`` (left, right, top, bottom): sides where the region meets kept input pixels (a crop edge)."""
    x = region.float()[None, None]
    if feather_px <= 0:
        return x[0, 0]
    depth = torch.zeros_like(x)
    for _ in range(int(feather_px)):  # F erosions, each over the whole map
        depth += x
        x = _erode(x, open_sides)
    t = depth[0, 0] / float(feather_px)
    return t * t * (3 - 2 * t)


def _open_sides(transform: PixelFrame) -> tuple[bool, bool, bool, bool]:
    """Which sides of the working image are crop edges of the input (left, right, top, bottom)."""
    (w, h), (sw, sh) = transform.working_size, transform.scaled_size or transform.working_size
    left, top = transform.offset
    return left > 0, sw - w - left > 0, top > 0, sh - h - top > 0


def _input_window(region: Tensor, transform: PixelFrame) -> tuple[int, int, int, int] | None:
    """Half-open ``(x0, y0, x1, y1)`` of the input pixels whose bilinear sample may touch ``region``; None if empty."""
    ys, xs = region.nonzero(as_tuple=True)
    if not len(xs):
        return None
    (sx, sy), (left, top) = transform.scale, transform.offset
    win, hin = transform.input_size
    # Working pixel u_w = (u_in + 0.5) * s - 0.5 - offset; a sample at u_w touches pixels floor(u_w), +1.
    x0 = math.floor((int(xs.min()) - 1 + 0.5 + left) / sx - 0.5)
    x1 = math.ceil((int(xs.max()) + 1 + 0.5 + left) / sx - 0.5) + 1
    y0 = math.floor((int(ys.min()) - 1 + 0.5 + top) / sy - 0.5)
    y1 = math.ceil((int(ys.max()) + 1 + 0.5 + top) / sy - 0.5) + 1
    return max(x0, 0), max(y0, 0), min(x1, win), min(y1, hin)


def compose_edited(original: Tensor, generated: Tensor, region: Tensor, transform: PixelFrame,
                   feather_px: int = 4) -> Tensor:
    """Blend the generator's picture into the input inside the feathered edit region.

    Args:
        original: ``(3, H_in, W_in)`` the input at its own resolution, uint8 or float in [0, 1].
        generated: ``(3, h, w)`` float in [0, 1], the generator's edited picture at the working size.
        region: ``(h, w)`` bool edit region (:func:`edit_region_mask`).
        transform: how the input became the working image (``input_size = (W_in, H_in)``, ``working_size = (w, h)``).
        feather_px: :func:`feather_alpha`'s ramp, working pixels.

    Returns:
        ``(3, H_in, W_in)`` of ``original``'s dtype: ``alpha * upsampled + (1 - alpha) * original`` (uint8
        rounded), and exactly ``original`` wherever alpha is 0 (outside the feathered region or the crop).
    """
    h, w = region.shape
    if tuple(transform.working_size) != (w, h) or tuple(generated.shape) != (3, h, w):
        raise ValueError(f"generated {tuple(generated.shape)} and region {tuple(region.shape)} must be at the "
                         f"transform's working size {tuple(transform.working_size)}")
    if tuple(original.shape) != (3, transform.input_size[1], transform.input_size[0]):
        raise ValueError(f"original {tuple(original.shape)} is not (3, H, W) of the transform's input size "
                         f"{tuple(transform.input_size)}")
    out = original.clone()
    window = _input_window(region, transform)
    if window is None:
        return out
    x0, y0, x1, y1 = window
    device = original.device
    grid, inside = sampling_grid(transform, window, device)
    alpha_work = feather_alpha(region.to(device), feather_px, _open_sides(transform))
    alpha = F.grid_sample(alpha_work[None, None], grid, mode="bilinear", padding_mode="border",
                          align_corners=False)[0, 0] * inside
    colour = F.grid_sample(generated[None].float().to(device), grid, mode="bilinear", padding_mode="border",
                           align_corners=False)[0].clamp(0, 1)
    patch = original[:, y0:y1, x0:x1]
    if patch.dtype == torch.uint8:
        blend = (alpha * colour * 255 + (1 - alpha) * patch.float()).round().clamp(0, 255).to(torch.uint8)
    else:
        blend = (alpha * colour + (1 - alpha) * patch).to(patch.dtype)
    out[:, y0:y1, x0:x1] = torch.where(alpha > 0, blend, patch)
    return out


def compose_edit(settings: ComposeSettings, generated: Tensor, original: Tensor | None, transform: PixelFrame,
                 before: ComposedMaps, after: ComposedMaps, edited_ids: Tensor) -> tuple[Tensor, Tensor | None]:
    """``(picture, region)``: ``mode='full'``: the generator's ``(3, h, w)`` picture and None (``original`` unused);
    ``'edited'``: :func:`compose_edited` ``(3, H_in, W_in)`` (``original``'s dtype) and the ``(h, w)`` edit region
    of the scenes' maps ``before`` / ``after`` and the objects ``edited_ids (K,)`` (:func:`edited_object_ids`)."""
    if settings.mode == "full":
        return generated, None
    if original is None:
        raise ValueError("compose='edited' needs the original picture")
    region = edit_region_mask(before, after, edited_ids, settings.dilate_px).cpu()
    return compose_edited(original, generated.detach().cpu(), region, transform, settings.feather_px), region
