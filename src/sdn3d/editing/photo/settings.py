"""The photo appearance's settings (:class:`PhotoSettings`), its fill methods and its source-map codes."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from torch import Tensor

from sdn3d.errors import UserInputError

__all__ = ["FILL_METHODS", "AUTO_THIN_PX", "SOURCE_NAMES", "SOURCE_COLORS", "PATCHMATCH_MAX_SIDE",
           "INPUT", "PHOTO", "MIRROR", "FALLBACK", "FILL", "RECOLORED", "SHADOW", "PhotoSettings", "PhotoSettingsError",
           "source_picture"]


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


def source_picture(source: Tensor) -> np.ndarray:
    """``(H, W, 3)`` uint8 picture of a :attr:`PhotoResult.source` map (colours :data:`SOURCE_COLORS`)."""
    lut = np.asarray(SOURCE_COLORS, np.uint8)
    return lut[source.cpu().numpy().astype(np.int64)]
