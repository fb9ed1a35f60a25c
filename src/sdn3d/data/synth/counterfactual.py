"""Counterfactual pairs (issue 41 item 4): a test frame re-rendered with one car turned in place, or without it.

For a chosen source frame of a sequence's test part and a target car in it, the generator renders the same
frame (same world, camera, variation, lighting and per-frame seed; every other car where it was) with only that
car changed:

- ``turn``: the car turned about its own vertical axis by ``angle_deg`` (added to its yaw ``ry``; its box centre,
  size, shape, FFD and colour unchanged), its shadow turned with it;
- ``delete``: the frame without the car, hence without its shadow.

Each pair comes with the masks a benchmark needs to score it (:func:`pair_masks`): the target car's pixels in the
counterfactual render (``target_mask``; empty for a delete), the *vacated* region (its pixels in the source that
it does not cover in the counterfactual: the source mask minus the target mask) and the *shadow band* (pixels
outside both car masks whose colour changed by more than :data:`SHADOW_THRESHOLD` in some channel: the car's
moved or removed shadow and ambient occlusion). Outside those three masks the counterfactual differs from the
source by at most :data:`SHADOW_THRESHOLD` per channel; a 0-degree turn reproduces the source frame bit for bit.

Files (``docs/DATA.md``, "Counterfactual pairs"): under ``counterfactual/<world>/<variation>/<frame>_<instance
id>/`` the source car's mask and, per pair, the render and its three masks (8-bit PNG, 255 = in the mask), listed
in ``counterfactual_pairs.json`` at the dataset root (:data:`PAIRS_NAME`).
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import numpy as np
from PIL import Image

from sdn3d.data.synth.edits import _footprint, footprints_overlap, project_full
from sdn3d.data.synth.layout import FrameObjects, World
from sdn3d.data.synth.stats import ObjectStats
from sdn3d.math3d.camera import Intrinsics

__all__ = [
    "PAIRS_NAME",
    "PAIRS_DIR",
    "PAIRS_FORMAT",
    "SHADOW_THRESHOLD",
    "Target",
    "eligible_targets",
    "turn_overlaps",
    "turned",
    "deleted",
    "pair_masks",
    "mask_png_bytes",
    "full_resolution_centre",
]

#: The pairs' index at the dataset root.
PAIRS_NAME = "counterfactual_pairs.json"
#: The pairs' files, under the dataset root.
PAIRS_DIR = "counterfactual"
#: ``format`` of :data:`PAIRS_NAME` (``version`` 1).
PAIRS_FORMAT = "sdn3d-counterfactual-pairs"
#: A pixel outside the car masks belongs to the shadow band when some channel changed by more than this (0-255).
SHADOW_THRESHOLD = 2
#: A turned footprint this close (metres) to another car's overlaps it (:func:`turn_overlaps`).
_TURN_MARGIN = 0.1


@dataclass(frozen=True)
class Target:
    """A counterfactual target: object ``index`` of regular frame ``frame``."""

    frame: int
    index: int


def eligible_targets(world: World, objects: FrameObjects, stats: ObjectStats, intrinsics: Intrinsics,
                     turns_deg: tuple[float, ...] = (), free: bool = True) -> list[int]:
    """Objects of a frame that may be a counterfactual target: well visible (at least 40 pixels or 0.2 % of the
    frame, half of its in-frame pixels visible, truncation <= 0.3) and more than 3 m ahead; with ``free``, also free
    to turn by every angle of ``turns_deg`` in place (:func:`turn_overlaps` finds no other car)."""
    min_pixels = max(40, int(0.002 * intrinsics.width * intrinsics.height))
    out = []
    for i in range(len(objects)):
        if not (stats.visible[i] >= min_pixels and stats.visible_fraction[i] >= 0.5 and stats.truncr[i] <= 0.3
                and objects.center[i, 2] > 3.0):
            continue
        if free and any(turn_overlaps(world, objects, i, a) for a in turns_deg):
            continue
        out.append(i)
    return out


def turn_overlaps(world: World, objects: FrameObjects, index: int, angle_deg: float,
                  margin: float = _TURN_MARGIN) -> list[int]:
    """Indices of the other objects whose ground footprint the object's footprint, turned in place by
    ``angle_deg``, comes within ``margin`` metres of."""
    dims = world.cars.dims[objects.track]
    rect = _footprint(objects.center[index], dims[index], float(objects.ry[index]) + math.radians(angle_deg))
    return [j for j in range(len(objects)) if j != index
            and footprints_overlap(rect, _footprint(objects.center[j], dims[j], float(objects.ry[j])), margin)]


def turned(objects: FrameObjects, index: int, angle_deg: float) -> FrameObjects:
    """``objects`` with object ``index`` turned in place by ``angle_deg`` (yaw wrapped to ``[-pi, pi)``; a 0-degree
    turn returns the yaws unchanged, bit for bit)."""
    ry = objects.ry.copy()
    if angle_deg != 0:
        ry[index] = float(np.remainder(ry[index] + math.radians(angle_deg) + math.pi, 2 * math.pi) - math.pi)
    return FrameObjects(objects.track.copy(), objects.center.copy(), ry, objects.moving.copy())


def deleted(objects: FrameObjects, index: int) -> FrameObjects:
    """``objects`` without object ``index`` (the others keep their order)."""
    return objects.subset(np.arange(len(objects)) != index)


def pair_masks(source_rgb: np.ndarray, source_mask: np.ndarray, target_rgb: np.ndarray, target_mask: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """``(vacated, shadow)`` ``(H, W)`` bool masks of a pair: the source car's pixels it no longer covers, and the
    pixels outside both car masks whose colour changed by more than :data:`SHADOW_THRESHOLD` in some channel."""
    vacated = source_mask & ~target_mask
    change = np.abs(source_rgb.astype(np.int16) - target_rgb.astype(np.int16)).max(axis=-1)
    shadow = (change > SHADOW_THRESHOLD) & ~(source_mask | target_mask)
    return vacated, shadow


def mask_png_bytes(mask: np.ndarray) -> bytes:
    """8-bit grey PNG of a ``(H, W)`` bool mask (255 = in the mask), fixed options like ``writer.png_bytes``."""
    buffer = io.BytesIO()
    Image.fromarray(np.where(mask, 255, 0).astype(np.uint8)).save(buffer, format="PNG", compress_level=1)
    return buffer.getvalue()


def full_resolution_centre(objects: FrameObjects, index: int) -> list[float]:
    """The object's projected 3D box centre in pixels of the 1242x375 frame (1 decimal), as the edit benchmark's
    ``from``."""
    uv = project_full(objects.center[index:index + 1])[0]
    return [round(float(uv[0]), 1), round(float(uv[1]), 1)]
