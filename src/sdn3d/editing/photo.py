"""Photo appearance: every edited object drawn with the input photo's own pixels, carried through its fitted 3D shape.

The textural generator re-synthesises an edited car from a five-number code; at CPU budgets it draws a blob.
``appearance='photo'`` (the default of ``sdn3d-edit``, :func:`sdn3d.editing.render.edit_image` and the demo's
grids) draws nothing from a code. At the **input's resolution** (:class:`~sdn3d.editing.frame.PixelFrame` gives the
input camera, :func:`input_intrinsics`):

1. *Who owns each pixel.* Objects that stay where they were keep their input pixels (their working-size
   masks, upsampled). Moved, turned, zoomed and duplicated objects are rasterized at their new pose
   (:func:`sdn3d.render.rasterize_meshes`, one call) and cover a pixel where they are nearer than the
   object that stays there (its rendered depth in the source rasterization, else its centre's): the edited
   scene's z-buffer decides who is in front.
2. *Vacated pixels* (the source footprint of every moved or deleted object, a few pixels around it, and a
   band of road below it for its old contact shadow) are filled by an inpainter (:data:`FILL_METHODS`:
   OpenCV's Telea, or the generator's background), before anything is drawn over them.
3. *Transfer.* For each pixel an edited object covers, the surface point (face and barycentrics) is carried
   to the object's source pose (same face, same barycentrics: edits are rigid), projected into the input and
   sampled there (bilinear; from a pre-filtered pyramid level when the car got smaller, so it does not
   alias), but only if that point was visible in the input: the source rasterization shows the same object
   there within :attr:`PhotoSettings.depth_tolerance`, and the pixel is inside the object's instance mask,
   eroded (no other object covers it). Else its **mirror image** across the vehicle's left-right plane
   (``z = 0`` of the canonical frame; templates and FFD are symmetric) is tried the same way. What is still
   unseen gets the **fallback**: the car's own body colour (its visible pixels, de-shaded) shaded for the new
   normal. An object amodally completed behind a deleted one (:func:`sdn3d.editing.apply.apply_edits`) has its
   freed pixels drawn the same way at its own pose.
4. *Shading follows the pose* (:func:`fit_light`): one directional light and an ambient term are fitted to
   the visible car pixels of the input (per-object albedo, least squares on log luminance, a grid over
   directions), and each transferred colour is multiplied by ``shade(new normal) / shade(source normal)``.
5. *Recolour* (:func:`recolor_pixels`): the body's pixels (the largest colour cluster of the car, in CIE
   Lab) move to the named colour's chroma and lightness, their variation (shading, reflections) kept;
   windows, tyres and lights (other clusters) are untouched.
6. A soft darkened footprint under a moved object is its new contact shadow.

:class:`PhotoResult` carries the picture and a per-pixel *source map* (:data:`SOURCE_NAMES`: input, photo,
mirror, fallback, fill, recolored, shadow) saying where each pixel came from; only ``input`` pixels are the
input's, bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import kornia.color
import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor

from sdn3d.editing.frame import PixelFrame, input_intrinsics, upsample_ids, working_to_input
from sdn3d.editing.ops import SetCode
from sdn3d.errors import UserInputError
from sdn3d.math3d.rotations import roty
from sdn3d.meshes.bank import MeshBank, default_bank
from sdn3d.render.maps import normal_map
from sdn3d.render.rasterize import Fragments, rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import ObjectTable, SceneCode
from sdn3d.scene.maps import compose_instances, posed_meshes

__all__ = ["APPEARANCES", "FILL_METHODS", "SOURCE_NAMES", "SOURCE_COLORS", "PhotoSettings", "PhotoSettingsError",
           "PhotoResult", "LightEstimate", "paints", "fit_light", "inpaint",
           "recolor_pixels", "vacated_hole", "fill_hole", "render_photo", "source_picture",
           "PhotoCache"]

#: ``photo``: the input's own pixels through each object's 3D shape (module doc); ``generator``: the textural
#: generator's pixels (the paper's).
APPEARANCES = ("photo", "generator")
#: How vacated pixels are filled: OpenCV's Telea (fast; the best weight-free fill by L1 and PSNR on a held-out
#: synthetic benchmark's delete and occluder entries, by 0.3-0.5 dB, but it smears bushes and facades across a large
#: hole), PatchMatch (PyPatchMatch: copies texture, plausible road on large holes, slower), ``auto`` (the default: Telea
#: for thin gaps, PatchMatch for large holes) or the generator's picture (needs the textural branch).
FILL_METHODS = ("telea", "patchmatch", "auto", "generator")
#: ``fill='auto'``: a hole part at most this many pixels from its edge everywhere is filled by Telea, else PatchMatch.
AUTO_THIN_PX = 6.0
#: Codes of :attr:`PhotoResult.source`.
SOURCE_NAMES = ("input", "photo", "mirror", "fallback", "fill", "recolored", "shadow")
#: Colour of each source code in :func:`source_picture` (sRGB uint8).
SOURCE_COLORS = ((40, 40, 40), (60, 170, 75), (70, 120, 230), (230, 80, 60), (240, 200, 60), (200, 90, 220),
                 (120, 120, 120))
INPUT, PHOTO, MIRROR, FALLBACK, FILL, RECOLORED, SHADOW = range(7)
#: PatchMatch runs on crops at most this many pixels on a side (larger ones are filled at a coarser scale).
PATCHMATCH_MAX_SIDE = 256


class PhotoSettingsError(UserInputError):
    """A bad photo-appearance setting (``photo.*`` of ``sdn3d-edit``)."""


@dataclass(frozen=True)
class PhotoSettings:
    """How :func:`render_photo` draws an edit.

    Attributes:
        fill: :data:`FILL_METHODS` for vacated pixels (default ``auto``).
        depth_tolerance: a carried point counts as visible when the source rasterization's depth there is
            within this fraction of its own depth (plus 5 cm).
        min_view_cos: ... and when the input saw its surface at least this squarely (cosine between the surface
            normal and the line of sight): a side seen edge-on in the input covers a pixel or two there and would be
            stretched over the whole side when the car turns.
        mask_erode_px: input pixels the upsampled instance masks are eroded by before they vouch for a pixel
            (None: one working pixel, ``ceil(1 / scale)``).
        hole_dilate_px: input pixels a vacated footprint grows by (its anti-aliased rim, its shadow's edge).
        shadow_band: height of the road band below a vacated footprint (its old contact shadow) as a fraction
            of the footprint's height.
        contact_shadow: darkening of the road under a moved object at its new place (0: none).
        relight: re-shade transferred pixels for their new normals (:func:`fit_light`).
        inpaint_radius: Telea's neighbourhood (input pixels).
        max_level: deepest pyramid level sampled when an object shrinks (2**level smaller).
    """

    fill: str = "auto"
    depth_tolerance: float = 0.03
    min_view_cos: float = 0.2
    mask_erode_px: int | None = None
    hole_dilate_px: int = 3
    shadow_band: float = 0.12
    contact_shadow: float = 0.3
    relight: bool = True
    inpaint_radius: int = 5
    max_level: int = 3

    def __post_init__(self) -> None:
        if self.fill not in FILL_METHODS:
            raise PhotoSettingsError(f"photo.fill must be one of {FILL_METHODS}, got {self.fill!r}")
        checks = (("depth_tolerance", self.depth_tolerance, 0.0, 1.0), ("shadow_band", self.shadow_band, 0.0, 1.0),
                  ("min_view_cos", self.min_view_cos, 0.0, 1.0),
                  ("contact_shadow", self.contact_shadow, 0.0, 1.0))
        for name, value, lo, hi in checks:
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= float(value) <= hi:
                raise PhotoSettingsError(f"photo.{name} must be a number in [{lo}, {hi}], got {value!r}")
        ints = (("hole_dilate_px", self.hole_dilate_px, 0, 64), ("inpaint_radius", self.inpaint_radius, 1, 32),
                ("max_level", self.max_level, 0, 6), ("mask_erode_px", self.mask_erode_px, 0, 16))
        for name, value, lo, hi in ints:
            if name == "mask_erode_px" and value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
                raise PhotoSettingsError(f"photo.{name} must be an integer in [{lo}, {hi}], got {value!r}")
        if not isinstance(self.relight, bool):
            raise PhotoSettingsError(f"photo.relight must be true or false, got {self.relight!r}")

    def to_dict(self) -> dict:
        return dict(self.__dict__)

    @classmethod
    def from_mapping(cls, node: Mapping | None) -> PhotoSettings:
        """Settings from a config mapping (``photo:`` of ``conf/edit.yaml`` / ``conf/bench.yaml``); unknown keys are
        refused by name."""
        values = {str(k): v for k, v in dict(node or {}).items()}
        unknown = sorted(set(values) - set(cls.__dataclass_fields__))
        if unknown:
            raise PhotoSettingsError(f"photo: unknown setting(s) {unknown}; the settings are "
                                     f"{sorted(cls.__dataclass_fields__)}")
        return cls(**values)


@dataclass(frozen=True)
class LightEstimate:
    """One directional light: ``shade(n) = ambient + (1 - ambient) max(0, n . direction)``.

    Attributes:
        direction: ``(3,)`` unit vector towards the light (camera frame); ambient: in (0, 1];
        gain: the fit's residual cut against constant shading (0: no better, 1: perfect); pixels: used.
    """

    direction: Tensor
    ambient: float
    gain: float
    pixels: int

    def shade(self, normals: Tensor) -> Tensor:
        """``(...,)`` shading of unit ``normals (..., 3)``."""
        lam = (normals * self.direction.to(normals)).sum(-1).clamp(min=0)
        return self.ambient + (1 - self.ambient) * lam

    def to_dict(self) -> dict:
        return {"direction": [round(float(x), 4) for x in self.direction], "ambient": round(self.ambient, 4),
                "gain": round(self.gain, 4), "pixels": self.pixels}


@dataclass
class PhotoResult:
    """Output of :func:`render_photo`.

    Attributes:
        image: ``(3, H_in, W_in)`` the edited picture (the original's dtype).
        source: ``(H_in, W_in)`` uint8 :data:`SOURCE_NAMES` code of each pixel.
        light: the fitted light (None: relighting off or not fitted).
        objects: ``{instance id: {pixels, photo, mirror, fallback (shares), ...}}`` per drawn object.
        warnings: what the user should know (an object none of whose surface the input shows, ...).
    """

    image: Tensor
    source: Tensor
    light: LightEstimate | None
    objects: dict[int, dict] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)

    def summary(self) -> dict:
        counts = torch.bincount(self.source.flatten().long(), minlength=len(SOURCE_NAMES))
        return {"source_pixels": {n: int(c) for n, c in zip(SOURCE_NAMES, counts.tolist(), strict=True)},
                "light": self.light.to_dict() if self.light is not None else None, "objects": self.objects,
                "warnings": list(self.warnings)}


class PhotoCache:
    """What :func:`render_photo` computes from the unedited scene alone, kept between edits of that one scene (an
    interactive editor redraws only what changed; ``sdn3d.editing.session``).

    It holds the source instance maps, the source rasterization, the fitted light and the filled vacated pixels per
    set of objects that left and stayed (the fill depends on nothing else). Every value is what the uncached call
    computes, so pictures are bit-identical with and without it; it is bound to the first ``(original, scene,
    transform, settings)`` it serves and refuses any other (a stale cache would draw another image's pixels).

    Args:
        max_fills: filled pictures kept (each ``3 x H x W`` float32: ~5.6 MB at 1242x375); the oldest goes first.
    """

    def __init__(self, max_fills: int = 8) -> None:
        self.max_fills = int(max_fills)
        self._bound: tuple | None = None
        self._values: dict[str, object] = {}
        self._fills: dict[tuple, Tensor] = {}

    def bind(self, original: Tensor, scene: SceneCode, transform: PixelFrame, settings: PhotoSettings) -> None:
        """Serve only this input, scene, transform and settings (checked on every call of :func:`render_photo`).

        Raises:
            ValueError: the cache already serves another scene or settings.
        """
        key = (original.data_ptr(), tuple(original.shape), original.dtype, id(scene), transform, settings)
        if self._bound is None:
            self._bound, self._refs = key, (original, scene)  # the refs keep the memory and the id in use
        elif self._bound != key:
            raise ValueError("PhotoCache serves one (original, scene, transform, settings); make one per scene")

    def get(self, name: str, make):
        """The value ``make()`` computed the first time ``name`` was asked for."""
        if name not in self._values:
            self._values[name] = make()
        return self._values[name]

    def fill(self, key: tuple, make) -> Tensor:
        """A copy of the filled picture of ``key`` (the objects that left and stayed), made by ``make()`` once."""
        if self.max_fills <= 0:
            return make()
        if key not in self._fills:
            while len(self._fills) >= self.max_fills:
                self._fills.pop(next(iter(self._fills)))
            self._fills[key] = make()
        return self._fills[key].clone()  # the caller draws into its picture


def paints(ops: Sequence[object]) -> dict[int, tuple[float, float, float]]:
    """``{instance id: sRGB paint}`` of the :class:`~sdn3d.editing.ops.SetCode` ops in ``ops`` that name a colour
    (the last one wins)."""
    return {int(op.instance_id): op.color for op in ops if isinstance(op, SetCode) and op.color is not None}


# -- frames --------------------------------------------------------------------------------------------


def _erode_ids(ids: Tensor, radius: int) -> Tensor:
    """``ids (H, W)`` with every pixel whose ``(2r+1)^2`` neighbourhood holds another id set to 0."""
    if radius <= 0:
        return ids
    x = ids[None, None].double()
    k = 2 * radius + 1
    hi = F.max_pool2d(F.pad(x, (radius,) * 4, mode="replicate"), k, stride=1)
    lo = -F.max_pool2d(F.pad(-x, (radius,) * 4, mode="replicate"), k, stride=1)
    return torch.where((hi == lo)[0, 0], ids, torch.zeros_like(ids))


def _dilate(mask: Tensor, radius: int) -> Tensor:
    if radius <= 0 or not bool(mask.any()):
        return mask
    return F.max_pool2d(mask[None, None].float(), 2 * radius + 1, stride=1, padding=radius)[0, 0] > 0


# -- light ---------------------------------------------------------------------------------------------


def _sphere(n: int) -> Tensor:
    """``(n, 3)`` float64 unit vectors spread evenly (Fibonacci sphere)."""
    k = torch.arange(n, dtype=torch.float64) + 0.5
    y = 1 - 2 * k / n
    r = (1 - y * y).sqrt()
    phi = math.pi * (3 - math.sqrt(5)) * k
    return torch.stack([r * phi.cos(), y, r * phi.sin()], 1)


def luminance(rgb: Tensor) -> Tensor:
    """``(...,)`` Rec. 709 luminance of ``rgb (..., 3)`` in [0, 1]."""
    return rgb @ rgb.new_tensor([0.2126, 0.7152, 0.0722])


def fit_light(colors: Tensor, normals: Tensor, groups: Tensor, directions: int = 256,
              ambients: tuple[float, ...] = (0.15, 0.25, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85)) -> LightEstimate | None:
    """Fit one directional light and an ambient term to object pixels (module doc, step 4).

    Each pixel's luminance is modelled as ``albedo[group] * shade(normal)``; per light the albedos are solved in
    closed form on log luminance, and the light with the least squared residual wins. Very dark and saturated
    pixels are left out, and so are lights below the horizon. Give body pixels only (:func:`body_pixels`): dark
    windows on top of a car would otherwise read as light from below.

    Args:
        colors: ``(P, 3)`` sRGB in [0, 1]; normals: ``(P, 3)`` unit camera-frame normals; groups: ``(P,)`` object
            index of each pixel (one albedo each).

    Returns:
        The best light, or None with fewer than 50 usable pixels.

    Example:
        >>> import torch
        >>> n = torch.nn.functional.normalize(torch.randn(2000, 3, generator=torch.Generator().manual_seed(0)), dim=1)
        >>> light = torch.tensor([0.0, -0.8, -0.6])
        >>> y = 0.6 * (0.3 + 0.7 * (n @ light).clamp(min=0))
        >>> fit = fit_light(y[:, None].expand(-1, 3), n, torch.zeros(2000, dtype=torch.long))
        >>> bool((fit.direction @ light.double()) > 0.98), round(fit.ambient, 2)
        (True, 0.35)
    """
    y = luminance(colors.double())
    keep = (y > 0.04) & (y < 0.97) & torch.isfinite(normals).all(1)
    if int(keep.sum()) < 50:
        return None
    y, n, g = y[keep], normals[keep].double(), groups[keep]
    _, g = torch.unique(g, return_inverse=True)
    groups_n = int(g.max()) + 1
    count = torch.bincount(g, minlength=groups_n).double()
    log_y = y.log()
    dirs = _sphere(directions)
    dirs = dirs[dirs[:, 1] <= 0.1]  # street scenes: the light comes from above the horizon (camera y points down)
    amb = torch.tensor(ambients, dtype=torch.float64)
    lam = (n @ dirs.T).clamp(min=0)  # (P, D)
    log_s = (amb[None, None, :] + (1 - amb[None, None, :]) * lam[..., None]).log().flatten(1)  # (P, D*A)
    resid = log_y[:, None] - log_s
    mean = torch.zeros(groups_n, resid.shape[1], dtype=torch.float64).index_add_(0, g, resid) / count[:, None]
    err = ((resid - mean[g]) ** 2).sum(0)
    flat = log_y - (torch.zeros(groups_n, dtype=torch.float64).index_add_(0, g, log_y) / count)[g]
    base = float((flat**2).sum())
    best = int(err.argmin())
    d, a = divmod(best, len(ambients))
    gain = 1 - float(err[best]) / base if base > 0 else 0.0
    return LightEstimate(dirs[d].float(), float(amb[a]), gain, int(keep.sum()))


# -- fills ---------------------------------------------------------------------------------------------


def inpaint(image: Tensor, hole: Tensor, method: str = "telea", radius: int = 5, patch_size: int = 3,
            keep_out: Tensor | None = None) -> Tensor:
    """``image (3, H, W)`` float in [0, 1] with ``hole (H, W)`` filled, each connected part of the hole on its own
    bounding box plus a margin (:func:`_inpaint_part`; ``method`` there, or ``'auto'``)."""
    import cv2

    if not bool(hole.any()):
        return image
    count, labels = cv2.connectedComponents(hole.numpy().astype(np.uint8), connectivity=8)
    depth = cv2.distanceTransform(hole.numpy().astype(np.uint8), cv2.DIST_L2, 3) if method == "auto" else None
    labels = torch.from_numpy(labels)
    for k in range(1, count):
        part = labels == k
        how = method
        if method == "auto":  # thin gaps smear little under Telea; large holes need copied texture
            how = "telea" if float(depth[part.numpy()].max()) <= AUTO_THIN_PX else "patchmatch"
        image = _inpaint_part(image, part, how, radius, patch_size, keep_out)
    return image


def _inpaint_part(image: Tensor, hole: Tensor, method: str, radius: int, patch_size: int,
                  keep_out: Tensor | None) -> Tensor:
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
    ys, xs = hole.nonzero(as_tuple=True)
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
        if keep_out is not None and bool(keep_out[y0:y1, x0:x1].any()):
            avoid = cv2.copyMakeBorder((keep_out[y0:y1, x0:x1] & ~hole[y0:y1, x0:x1]).numpy().astype(np.uint8),
                                       1, 1, 1, 1, cv2.BORDER_CONSTANT, value=0)
        full = crop.shape[1], crop.shape[0]
        shrink = min(1.0, PATCHMATCH_MAX_SIDE / max(full))
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
    vacated = torch.isin(ids, gone) & (ids != 0)
    hole = _dilate(vacated, settings.hole_dilate_px)
    if settings.shadow_band > 0 and bool(vacated.any()):
        for k in gone.tolist():
            one = ids == k
            rows = one.any(1).nonzero().flatten()
            if not len(rows):
                continue
            band = max(1, round(settings.shadow_band * float(rows.max() - rows.min() + 1)))
            below = F.max_pool2d(F.pad(one[None, None].float(), (0, 0, band, 0)), (band + 1, 1), stride=1)[0, 0] > 0
            hole |= _dilate(below, 1)
    return hole & ~keep


def fill_hole(image: Tensor, hole: Tensor, settings: PhotoSettings, keep_out: Tensor | None = None,
              fill: Tensor | None = None) -> Tensor:
    """``image (3, H, W)`` with ``hole`` filled by ``settings.fill`` (:data:`FILL_METHODS`; ``fill (3, H, W)``: the
    generator's picture at this size, for ``'generator'``); ``keep_out``: pixels PatchMatch must not copy."""
    if not bool(hole.any()):
        return image.clone()
    if settings.fill == "generator":
        if fill is None:
            raise PhotoSettingsError("photo.fill=generator needs the generator's picture (the textural branch)")
        return torch.where(hole[None], fill.clamp(0, 1).to(image.dtype), image)
    return inpaint(image, hole, settings.fill, settings.inpaint_radius, keep_out=keep_out)


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
        body[sel[_paint(_lab(colors[sel]))]] = True
    return body


# -- recolour ------------------------------------------------------------------------------------------


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


def recolor_pixels(colors: Tensor, target_rgb: tuple[float, float, float]) -> tuple[Tensor, Tensor, dict]:
    """Repaint a car's body (module doc, step 5).

    Args:
        colors: ``(P, 3)`` sRGB in [0, 1], the car's pixels; target_rgb: the paint, sRGB in [0, 1].

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
    lab = _lab(colors)
    body = _paint(lab)
    target = _lab(torch.tensor([target_rgb], dtype=colors.dtype))[0]
    shift = target - lab[body].mean(0)
    new_lab = lab + shift
    new = _rgb(new_lab).clamp(0, 1)
    out = torch.where(body[:, None], new, colors)
    delta = float((_lab(out[body]).mean(0) - target).norm())
    return out, body, {"body_share": float(body.double().mean()), "delta_e": delta}


def _lab(rgb: Tensor) -> Tensor:
    """``(P, 3)`` CIE Lab of sRGB rows in [0, 1] (kornia's conversion)."""
    return kornia.color.rgb_to_lab(rgb.float().clamp(0, 1).T[:, :, None])[:, :, 0].T


def _rgb(lab: Tensor) -> Tensor:
    return kornia.color.lab_to_rgb(lab.float().T[:, :, None], clip=True)[:, :, 0].T


# -- transfer ------------------------------------------------------------------------------------------


@dataclass
class _Raster:
    """A rasterization at the input's resolution: ``rows (G,)`` of the table, ``verts (G, V, 3)``, ``faces``,
    fragments ``(1, H, W)``."""

    rows: Tensor
    verts: Tensor
    faces: Tensor
    frags: Fragments


def _rasterize(rows: Tensor, verts: Tensor, faces: Tensor, K: Tensor, size: tuple[int, int]) -> _Raster:
    g = len(rows)
    frags = rasterize_meshes(verts.double(), faces, K, RasterSettings(image_size=size),
                             mesh_to_image=torch.zeros(g, dtype=torch.long), batch_size=1)
    return _Raster(rows, verts.double(), faces, frags)


def _surface(r: _Raster, pix: Tensor) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    """``(mesh (P,), vertex ids (P, 3), barycentrics (P, 3), camera-facing unit normal (P, 3))`` at flat pixel
    indices ``pix (P,)`` of ``r`` (all covered)."""
    f_all = r.frags.pix_to_face.view(-1)[pix]
    mesh = r.frags.pix_to_mesh.view(-1)[pix]
    nf = r.faces.shape[1]
    vid = r.faces[mesh, f_all - mesh * nf]  # (P, 3)
    bary = r.frags.bary.view(-1, 3)[pix].double()
    tri = r.verts[mesh[:, None], vid]  # (P, 3, 3)
    point = (bary[..., None] * tri).sum(1)
    normal = F.normalize(torch.linalg.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], dim=-1), dim=-1)
    normal = torch.where(((normal * point).sum(-1) > 0)[:, None], -normal, normal)
    return mesh, vid, bary, normal


def _project(points: Tensor, K: Tensor) -> tuple[Tensor, Tensor]:
    """``(uv (P, 2), in front (P,))`` pixel coordinates of camera-frame ``points (P, 3)``."""
    z = points[:, 2]
    front = z > RasterSettings.near
    zs = torch.where(front, z, torch.ones_like(z))
    uv = torch.stack([K[0, 0] * points[:, 0] / zs + K[0, 2], K[1, 1] * points[:, 1] / zs + K[1, 2]], 1)
    return uv, front


def _visible(points: Tensor, mesh: Tensor, iid: Tensor, src: _Raster, vis_ids: Tensor, K: Tensor,
             tolerance: float) -> tuple[Tensor, Tensor]:
    """``(visible (P,), uv (P, 2))``: is each source-pose point ``points (P, 3)`` of source mesh ``mesh (P,)``
    (instance ``iid (P,)``) seen in the input (module doc, step 3)?"""
    height, width = vis_ids.shape
    uv, front = _project(points, K)
    j, i = torch.floor(uv[:, 0] + 0.5).long(), torch.floor(uv[:, 1] + 0.5).long()
    inside = front & (j >= 0) & (j < width) & (i >= 0) & (i < height) & torch.isfinite(uv).all(1)
    flat = (i.clamp(0, height - 1) * width + j.clamp(0, width - 1))
    same = src.frags.pix_to_mesh.view(-1)[flat] == mesh
    depth = src.frags.depth.view(-1)[flat].double()
    z = points[:, 2]
    near = (depth - z).abs() <= tolerance * z.abs() + 0.05
    ok = inside & same & near & (vis_ids.view(-1)[flat] == iid)
    return ok, uv


def _view_cos(points: Tensor, normals: Tensor) -> Tensor:
    """``(P,)`` ``|cos|`` of the angle between each surface normal and the line of sight to its point (camera at the
    origin): 1 seen squarely, 0 edge-on."""
    return (F.normalize(points, dim=-1) * normals).sum(-1).abs()


def _pyramid(image: Tensor, levels: int) -> list[Tensor]:
    out = [image[None].float()]
    for _ in range(levels):
        prev = out[-1]
        if min(prev.shape[-2:]) < 4:
            break
        out.append(F.interpolate(prev, scale_factor=0.5, mode="bilinear", antialias=True, align_corners=False,
                                 recompute_scale_factor=False))
    return out


def _sample(pyramid: list[Tensor], uv: Tensor, level: Tensor) -> Tensor:
    """``(P, 3)`` bilinear samples at input pixels ``uv (P, 2)``, blended between pyramid levels ``level (P,)``."""
    height, width = pyramid[0].shape[-2:]
    grid = torch.stack([(uv[:, 0] + 0.5) / width * 2 - 1, (uv[:, 1] + 0.5) / height * 2 - 1], 1)
    grid = grid.float()[None, None]  # (1, 1, P, 2): normalised coordinates are the same at every level
    samples = torch.stack([F.grid_sample(p, grid, mode="bilinear", padding_mode="border",
                                         align_corners=False)[0, :, 0].T for p in pyramid])  # (L, P, 3)
    level = level.clamp(0, len(pyramid) - 1).float()
    lo = level.floor().long()
    hi = (lo + 1).clamp(max=len(pyramid) - 1)
    t = (level - lo.float())[:, None]
    idx = torch.arange(len(uv))
    return samples[lo, idx] * (1 - t) + samples[hi, idx] * t


def _same_pose(before: ObjectTable, after: ObjectTable, rb: Tensor, ra: Tensor) -> Tensor:
    return ((before.location[rb] - after.location[ra]).abs().amax(1) < 1e-9) & (
        (before.ry[rb] - after.ry[ra]).abs() < 1e-9)


def _origins(before: ObjectTable, after: ObjectTable) -> Tensor:
    """``(N_after,)`` row in ``before`` of each object of ``after`` (same id; for a duplicate, the object with the
    same template, size and shape), -1 where none."""
    origin = torch.full((len(after),), -1, dtype=torch.long)
    pairs = (after.instance_id[:, None] == before.instance_id[None, :]).nonzero()
    origin[pairs[:, 0]] = pairs[:, 1]
    for a in (origin < 0).nonzero().flatten().tolist():
        same = ((before.template_id == after.template_id[a]) & (before.dims == after.dims[a]).all(1)
                & (before.phi == after.phi[a]).flatten(1).all(1))
        if bool(same.any()):
            origin[a] = int(same.nonzero()[0])
    return origin


def _box_floor(objects: ObjectTable, row: int, grow: float = 1.1) -> Tensor:
    """``(4, 3)`` camera-frame corners of an object's bottom face, grown by ``grow``."""
    l, _, w = objects.dims[row].tolist()
    c = objects.location[row].double()
    corners = torch.tensor([[1, 1], [1, -1], [-1, -1], [-1, 1]], dtype=torch.float64) * 0.5 * grow
    local = torch.stack([corners[:, 0] * l, torch.zeros(4, dtype=torch.float64), corners[:, 1] * w], 1)
    return local @ roty(objects.ry[row].double()).T + c


def _contact_shadow(objects: ObjectTable, rows: list[int], K: Tensor, size: tuple[int, int]) -> Tensor:
    """``(H, W)`` float soft footprint in [0, 1] of the objects' bottom faces (their new contact shadows)."""
    import cv2

    height, width = size
    canvas = np.zeros((height, width), np.float32)
    for row in rows:
        uv, front = _project(_box_floor(objects, row), K)
        if not bool(front.all()) or not bool(torch.isfinite(uv).all()):
            continue
        poly = uv.numpy()
        if np.abs(poly).max() > 1e5:
            continue
        hull = cv2.convexHull(np.round(poly * 4).astype(np.int32))
        layer = np.zeros_like(canvas)
        cv2.fillConvexPoly(layer, hull, 1.0, lineType=cv2.LINE_AA, shift=2)
        span = max(float(poly[:, 1].max() - poly[:, 1].min()), 2.0)
        sigma = max(0.6, 0.25 * span)
        canvas = np.maximum(canvas, cv2.GaussianBlur(layer, (0, 0), sigma))
    return torch.from_numpy(canvas)


def source_picture(source: Tensor) -> np.ndarray:
    """``(H, W, 3)`` uint8 picture of a :attr:`PhotoResult.source` map (colours :data:`SOURCE_COLORS`)."""
    lut = np.asarray(SOURCE_COLORS, np.uint8)
    return lut[source.cpu().numpy().astype(np.int64)]


def render_photo(original: Tensor, transform: PixelFrame, scene: SceneCode, edited: SceneCode,
                 bank: MeshBank | None = None, settings: PhotoSettings | None = None,
                 recolor: Mapping[int, tuple[float, float, float]] | None = None,
                 generated: Tensor | None = None, cache: PhotoCache | None = None) -> PhotoResult:
    """Draw the edit of ``scene`` into ``edited`` with the input's own pixels (module doc).

    Args:
        original: ``(3, H_in, W_in)`` the input at its resolution, uint8 or float in [0, 1].
        transform: how the input became the scenes' working image.
        scene, edited: the de-rendered scene and its edit (:func:`~sdn3d.editing.apply.apply_edits`).
        bank: the objects' template meshes (default: the 8 templates).
        recolor: ``{instance id: sRGB paint}`` of objects to repaint (``recolor`` ops with a named colour).
        generated: ``(3, h, w)`` the generator's edited picture at the working size, for ``fill='generator'``.
        cache: what a previous call on the same ``original``, ``scene``, ``transform`` and ``settings`` computed from
            the unedited scene alone (:class:`PhotoCache`; the result is the same bit for bit); None: nothing kept.

    Returns:
        :class:`PhotoResult`; pixels no edit touches are the input's, bit for bit.
    """
    settings = settings or PhotoSettings()
    bank = bank or default_bank()
    recolor = dict(recolor or {})
    w_in, h_in = transform.input_size
    if tuple(original.shape) != (3, h_in, w_in):
        raise ValueError(f"original {tuple(original.shape)} is not (3, H, W) of the transform's input size "
                         f"{tuple(transform.input_size)}")
    if settings.fill == "generator" and generated is None:
        raise PhotoSettingsError("photo.fill=generator needs the generator's picture (the textural branch)")
    size = (h_in, w_in)
    if cache is None:
        cache = PhotoCache(max_fills=0)
    cache.bind(original, scene, transform, settings)
    image = cache.get("image", lambda: original.float() / 255 if original.dtype == torch.uint8
                      else original.float().clone())
    K = input_intrinsics(scene.intrinsics, transform).matrix(dtype=torch.float64)
    before, after = scene.objects, edited.objects
    warnings: list[str] = []

    # Which objects stay, move, go, grow (step 1).
    origin = _origins(before, after)
    stays = torch.zeros(len(after), dtype=torch.bool)
    has = origin >= 0
    same_id = has & (after.instance_id == before.instance_id[origin.clamp(min=0)])
    if bool(same_id.any()):
        ra = same_id.nonzero().flatten()
        stays[ra] = _same_pose(before, after, origin[ra], ra)
    moved = ~stays & has & after.has_geometry
    gone_ids = before.instance_id[~torch.isin(before.instance_id, after.instance_id[stays])]
    erode = settings.mask_erode_px
    if erode is None:
        erode = max(1, math.ceil(1 / min(transform.scale)))

    src_ids = cache.get("src_ids", lambda: upsample_ids(compose_instances(scene, bank).cpu(), transform))
    vis_ids = cache.get("vis_ids", lambda: _erode_ids(src_ids, erode))
    own = torch.where(torch.isin(src_ids, after.instance_id[stays]), src_ids, torch.zeros_like(src_ids))
    # Freed pixels an object that stays now covers (amodal completion in apply_edits).
    grown_rows = []
    for a in stays.nonzero().flatten().tolist():
        b = int(origin[a])
        gained = after.mask[a] & ~before.mask[b]
        if bool(gained.any()):
            up = upsample_ids(gained.long(), transform).bool() & (own == 0)
            own = torch.where(up, after.instance_id[a], own)
            grown_rows.append(a)

    def source_raster() -> _Raster:
        src_rows, src_verts, src_faces = posed_meshes(before, bank)
        return _rasterize(src_rows.cpu(), src_verts.cpu(), src_faces.cpu(), K, size)

    src = cache.get("src", source_raster)
    src_row_to_mesh = torch.full((len(before),), -1, dtype=torch.long)
    src_row_to_mesh[src.rows] = torch.arange(len(src.rows))

    # Light (step 4): visible pixels of every source object with geometry; only when something is drawn.
    light = None
    src_normals = None
    if settings.relight and len(src.rows) and (bool(moved.any()) or grown_rows):
        src_normals, light = cache.get("light", lambda: _source_light(src, vis_ids, before, image))
    shade = light.shade if light is not None else None

    # Vacated pixels (step 2); the source pixels of the objects that stay are kept.
    keep = (src_ids != 0) & torch.isin(src_ids, after.instance_id[stays])
    hole = vacated_hole(src_ids, gone_ids, keep, settings)
    if settings.fill == "generator":  # the generator's picture changes with every edit: nothing to keep
        out = fill_hole(image, hole, settings, src_ids != 0, working_to_input(generated, transform))
    else:  # the hole and its fill depend only on which objects left and which stayed
        stay_ids = after.instance_id[stays]
        key = (tuple(sorted(gone_ids.tolist())), tuple(sorted(stay_ids.tolist())))
        out = cache.fill(key, lambda: fill_hole(image, hole, settings, src_ids != 0))
    source = torch.where(hole, FILL, INPUT).to(torch.uint8)

    # Contact shadows of moved objects, on the road only (drawn objects cover the rest below).
    moved_rows = moved.nonzero().flatten().tolist()
    if settings.contact_shadow > 0 and moved_rows:
        soft = _contact_shadow(after, moved_rows, K, size)
        soft = torch.where(own != 0, torch.zeros_like(soft), soft)
        out = out * (1 - settings.contact_shadow * soft)[None]
        source = torch.where((soft > 0.02) & (source == INPUT), SHADOW, source).to(torch.uint8)

    # Target rasterization of the drawn objects (moved ones, and the ones that grew) at their poses.
    draw_rows = torch.tensor(sorted(set(moved_rows) | set(grown_rows)), dtype=torch.long)
    objects: dict[int, dict] = {}
    if len(draw_rows):
        tgt_all_rows, tgt_verts, tgt_faces = posed_meshes(after, bank)
        keep = torch.isin(tgt_all_rows.cpu(), draw_rows)
        tgt = _rasterize(tgt_all_rows.cpu()[keep], tgt_verts.cpu()[keep], tgt_faces.cpu()[keep], K, size)
        out, source, objects = _draw(out, source, image, own, src, tgt, before, after, origin, moved, src_row_to_mesh,
                                     src_ids, vis_ids, K, settings, shade, src_normals, warnings)
        for a in moved_rows:
            if int(after.instance_id[a]) not in objects:
                warnings.append(f"object {int(after.instance_id[a])}: after the edit it lies outside the picture "
                                "(nothing drawn)")

    # Recolour (step 5): the object's pixels in the result.
    final_own = own.clone()
    for iid, info in objects.items():
        final_own.view(-1)[info.pop("_pixels")] = iid
    for iid, rgb in recolor.items():
        region = final_own == int(iid)
        if not bool(region.any()):
            warnings.append(f"recolor: object {iid} has no pixels in the picture")
            continue
        colors = out.permute(1, 2, 0)[region]
        new, body, stats = recolor_pixels(colors, tuple(rgb))
        flat = out.permute(1, 2, 0).clone()
        flat[region] = new
        out = flat.permute(2, 0, 1)
        repainted = torch.zeros_like(region)
        repainted[region] = (new != colors).any(1)
        source = torch.where(repainted & (source == INPUT), RECOLORED, source).to(torch.uint8)
        objects.setdefault(int(iid), {}).update({"recolor": {"color": [round(float(c), 4) for c in rgb], **stats}})
    result = out.clamp(0, 1)
    changed = source != INPUT
    if original.dtype == torch.uint8:
        result = torch.where(changed[None], (result * 255 + 0.5).floor().clamp(0, 255).to(torch.uint8), original)
    else:
        result = torch.where(changed[None], result.to(original.dtype), original)
    return PhotoResult(result, source, light, objects, warnings)


def _source_light(src: _Raster, vis_ids: Tensor, before: ObjectTable,
                  image: Tensor) -> tuple[Tensor, LightEstimate | None]:
    """``(normals (H*W, 3) float64 of the source rasterization, the light fitted to the visible car pixels or
    None)`` (step 4 of the module doc: the unedited scene alone decides both)."""
    src_normals = normal_map(src.frags, src.verts, src.faces)[0].permute(1, 2, 0).reshape(-1, 3).double()
    mesh_at = src.frags.pix_to_mesh.view(-1)
    vis = (mesh_at >= 0) & (vis_ids.view(-1) == torch.where(
        mesh_at >= 0, before.instance_id[src.rows[mesh_at.clamp(min=0)]], -1))
    pix = vis.nonzero().flatten()
    pixels = image.permute(1, 2, 0).reshape(-1, 3)
    pix = pix[body_pixels(pixels[pix], mesh_at[pix])]
    if len(pix) > 6000:  # evenly spread: plenty for four numbers and the albedos
        pix = pix[torch.linspace(0, len(pix) - 1, 6000).long()]
    light = fit_light(pixels[pix], src_normals[pix], mesh_at[pix])
    if light is not None and light.gain < 0.05:
        light = None  # no better than constant shading: do not re-shade
    return src_normals, light


def _draw(out: Tensor, source: Tensor, image: Tensor, own: Tensor, src: _Raster, tgt: _Raster,
          before: ObjectTable, after: ObjectTable, origin: Tensor, moved: Tensor, src_row_to_mesh: Tensor,
          src_ids: Tensor, vis_ids: Tensor, K: Tensor, settings: PhotoSettings, shade, src_normals: Tensor | None,
          warnings: list[str]) -> tuple[Tensor, Tensor, dict[int, dict]]:
    """Steps 1 and 3 of the module doc for the objects of ``tgt``: who wins each pixel, then transfer."""
    height, width = own.shape
    t_mesh = tgt.frags.pix_to_mesh.view(-1)
    covered = (t_mesh >= 0).nonzero().flatten()
    row = tgt.rows[t_mesh[covered]]  # row in `after`
    iid = after.instance_id[row]
    own_flat = own.view(-1)[covered]
    is_moved = moved[row]
    # Depth of what stays at each pixel: its rendered source depth where the source shows it, else its centre's.
    stay_row = torch.searchsorted(before.instance_id.sort().values, own_flat.clamp(min=0))
    order = before.instance_id.argsort()
    stay_b = order[stay_row.clamp(max=max(len(order) - 1, 0))] if len(order) else stay_row
    src_mesh_here = src.frags.pix_to_mesh.view(-1)[covered]
    stay_depth = torch.where(src_mesh_here == src_row_to_mesh[stay_b], src.frags.depth.view(-1)[covered].double(),
                             before.center[stay_b, 2].double())
    t_depth = tgt.frags.depth.view(-1)[covered].double()
    # A moved object wins where nothing stays or it is nearer; one that grew draws only the pixels it gained.
    gained = (own_flat == iid) & (src_ids.view(-1)[covered] != iid)
    wins = torch.where(is_moved, (own_flat == 0) | (t_depth < stay_depth), gained)
    pix, row, iid, is_moved = covered[wins], row[wins], iid[wins], is_moved[wins]
    if not len(pix):
        return out, source, {}
    mesh, vid, bary, normal_t = _surface(tgt, pix)
    b_row = origin[row]
    s_mesh = src_row_to_mesh[b_row]
    has_src = s_mesh >= 0
    s_mesh_c = s_mesh.clamp(min=0)
    tri_s = src.verts[s_mesh_c[:, None], vid] if len(src.rows) else torch.zeros(len(pix), 3, 3, dtype=torch.float64)
    point_s = (bary[..., None] * tri_s).sum(1)
    normal_s = F.normalize(torch.linalg.cross(tri_s[:, 1] - tri_s[:, 0], tri_s[:, 2] - tri_s[:, 0], dim=-1), dim=-1)
    # Same face, same winding: orient the source normal as the target one was (edits are rigid).
    tri_t = tgt.verts[mesh[:, None], vid]
    raw_t = F.normalize(torch.linalg.cross(tri_t[:, 1] - tri_t[:, 0], tri_t[:, 2] - tri_t[:, 0], dim=-1), dim=-1)
    normal_s = torch.where(((raw_t * normal_t).sum(-1) < 0)[:, None], -normal_s, normal_s)
    src_iid = before.instance_id[b_row.clamp(min=0)]
    ok_photo, uv_photo = _visible(point_s, s_mesh, src_iid, src, vis_ids, K, settings.depth_tolerance)
    ok_photo &= has_src & (_view_cos(point_s, normal_s) >= settings.min_view_cos)
    # Mirror across the vehicle's left-right plane (local z = 0).
    rot = roty(before.ry[b_row.clamp(min=0)].double())  # (P, 3, 3)
    centre = before.center[b_row.clamp(min=0)].double()
    flip = torch.tensor([1.0, 1.0, -1.0], dtype=torch.float64)
    local = torch.einsum("pji,pj->pi", rot, point_s - centre) * flip
    point_m = torch.einsum("pij,pj->pi", rot, local) + centre
    normal_m = torch.einsum("pij,pj->pi", rot, torch.einsum("pji,pj->pi", rot, normal_s) * flip)
    ok_mirror, uv_mirror = _visible(point_m, s_mesh, src_iid, src, vis_ids, K, settings.depth_tolerance)
    ok_mirror &= has_src & ~ok_photo & (_view_cos(point_m, normal_m) >= settings.min_view_cos)

    # Sampling level: how much smaller the object got here (depth ratio), only when it shrank.
    z_t = tgt.frags.depth.view(-1)[pix].double()
    level = (z_t / point_s[:, 2].clamp(min=1e-3)).clamp(min=1.0).log2()
    pyramid = _pyramid(image, settings.max_level)
    uv = torch.where(ok_photo[:, None], uv_photo, uv_mirror)
    color = _sample(pyramid, uv, level).double()
    n_src = torch.where(ok_photo[:, None], normal_s, normal_m)
    if shade is not None:
        ratio = (shade(normal_t) / shade(n_src).clamp(min=1e-3)).clamp(0.5, 2.0)
        color = color * ratio[:, None]
    seen = ok_photo | ok_mirror

    # Fallback: the object's own body colour, de-shaded, shaded for the new normal.
    objects: dict[int, dict] = {}
    fallback = torch.zeros_like(color)
    img_flat = image.permute(1, 2, 0).reshape(-1, 3).double()
    for r in row.unique().tolist():
        sel = row == r
        b = int(origin[r])
        name = int(after.instance_id[r])
        visible_px = (vis_ids.view(-1) == int(before.instance_id[b])).nonzero().flatten() if b >= 0 else pix[:0]
        if len(visible_px):
            colors = img_flat[visible_px]
            if shade is not None and src_normals is not None:
                s = shade(src_normals[visible_px]).clamp(min=0.2)
                colors = colors / s[:, None]
            albedo = colors.median(0).values
        else:
            albedo = torch.full((3,), 0.5, dtype=torch.float64)
            warnings.append(f"object {name}: none of its surface is visible in the input; drawn in grey from its shape")
        s_new = shade(normal_t[sel]) if shade is not None else (0.55 + 0.45 * (-normal_t[sel, 1]).clamp(min=0))
        fallback[sel] = albedo[None] * s_new[:, None]
        n = int(sel.sum())
        objects[name] = {"pixels": n, "photo": round(float(ok_photo[sel].double().mean()), 4),
                         "mirror": round(float(ok_mirror[sel].double().mean()), 4),
                         "fallback": round(float((~seen[sel]).double().mean()), 4), "moved": bool(moved[r]),
                         "_pixels": pix[sel]}
        if len(visible_px) and n >= 50 and not bool(seen[sel].any()) and bool(moved[r]):
            warnings.append(f"object {name}: none of its surface is visible in the input (behind the camera, off the "
                            "frame or hidden); drawn from its mean colour")
    color = torch.where(seen[:, None], color, fallback).clamp(0, 1)
    flat = out.permute(1, 2, 0).reshape(-1, 3).clone()
    flat[pix] = color.float()
    codes = torch.where(ok_photo, PHOTO, torch.where(ok_mirror, MIRROR, FALLBACK)).to(torch.uint8)
    source = source.clone()
    source.view(-1)[pix] = codes
    return flat.view(height, width, 3).permute(2, 0, 1), source, objects

