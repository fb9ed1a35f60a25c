"""Editing-benchmark pairs with exact ground truth: edit a frame's 3D scene, render the result.

For a source frame, a few cars are picked and edited in 3D: ``modify`` moves a car on the
ground (a new bottom-centre position on the road, so it still stands on the ground) and/or
adds to its yaw; ``delete`` removes it. The edited scene is rendered as a new frame of the same
sequence (see ``generate.py``: numbers after the sequence's regular frames), which is the
exact target of the edit. The operations are described in the 3D-SDN benchmark format
(:mod:`sdn3d.data.edit_benchmark`), in pixels of the 1242x375 Virtual KITTI frame:

- ``from``: projection of the car's 3D box centre in the source frame (1 decimal);
- ``to``: projection of the moved centre, and ``roi = [top, left, bottom, right]``: the tight 2D
  box of the moved car's projected 3D box, clipped to the frame (``to = {}`` for a pure rotation);
- ``zoom = |c_source| / |c_target|`` (3 decimals) and the yaw increment ``ry`` (3 decimals).

The yaw increment is drawn already rounded, so it is exact; ``to`` and ``zoom`` are rounded
from the exact target (decoding them moves a car by a few millimetres at most).
Cars are only picked when their projected centre is unambiguous (no other visible car within
12 px) and they are well visible (visible share >= 0.5, truncation <= 0.3).

An *occluder removed* pair (:func:`occluder_candidates`, the paper's Fig. 4d / 6a) deletes a car in front
of a partly hidden one; its target shows the hidden car whole, which only a method that completes the hidden
car (3D-SDN redraws it from its geometry) can match. Such entries carry ``kind = 'occluder_removed'``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.data.synth.layout import FrameObjects, World
from sdn3d.data.synth.stats import ObjectStats
from sdn3d.math3d.camera import VKITTI_INTRINSICS, Intrinsics

__all__ = [
    "sample_edit",
    "occluder_candidates",
    "OccluderCandidates",
    "remove_occluder",
    "hidden_min_pixels",
    "MAX_HIDDEN_FRACTION",
    "project_full",
    "footprints_overlap",
    "DEFAULT_DELETE_SHARE",
]

_MIN_SEPARATION = 12.0  # full-resolution pixels between projected centres
_MAX_TRIES = 25
#: A partly hidden car of an occluder-removed pair shows at most this share of its in-frame pixels.
MAX_HIDDEN_FRACTION = 0.8
#: :func:`sample_edit`: the chance that a car an edit pair picks is deleted (the share every benchmark tree was drawn
#: with; ``SynthConfig.edit_delete_share``).
DEFAULT_DELETE_SHARE = 0.15


def project_full(points: np.ndarray) -> np.ndarray:
    """``(N, 3)`` camera-frame points -> ``(N, 2)`` pixels of the 1242x375 Virtual KITTI frame."""
    k = VKITTI_INTRINSICS
    z = np.maximum(points[:, 2], 1e-6)
    return np.stack([k.fx * points[:, 0] / z + k.cx, k.fy * points[:, 1] / z + k.cy], axis=1)


def _footprint(center: np.ndarray, dims: np.ndarray, ry: float) -> np.ndarray:
    """``(4, 2)`` (x, z) corners of a car's ground rectangle."""
    c, s = math.cos(ry), math.sin(ry)
    half_l, half_w = dims[0] / 2, dims[2] / 2
    local = np.array([[half_l, half_w], [half_l, -half_w], [-half_l, -half_w], [-half_l, half_w]])
    # R_y(ry) maps canonical (x, z) to camera (c x + s z, -s x + c z).
    return np.stack([c * local[:, 0] + s * local[:, 1], -s * local[:, 0] + c * local[:, 1]], 1) + center[[0, 2]]


def footprints_overlap(a: np.ndarray, b: np.ndarray, margin: float = 0.3) -> bool:
    """Whether two ``(4, 2)`` rectangles, each grown by ``margin``, overlap (separating axis test)."""
    for rect in (a, b):
        for i in range(2):
            axis = rect[i + 1] - rect[i]
            axis = axis / max(np.linalg.norm(axis), 1e-9)
            pa, pb = a @ axis, b @ axis
            if pa.max() + margin < pb.min() or pb.max() + margin < pa.min():
                return False
    return True


def _roi(center: np.ndarray, dims: np.ndarray, ry: float) -> list[int]:
    """``[top, left, bottom, right]`` of the projected 3D box at full resolution, clipped to the frame."""
    c, s = math.cos(ry), math.sin(ry)
    signs = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    local = signs * dims
    rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    uv = project_full(local @ rot.T + center)
    k = VKITTI_INTRINSICS
    left, right = np.clip([uv[:, 0].min(), uv[:, 0].max()], 0, k.width - 1)
    top, bottom = np.clip([uv[:, 1].min(), uv[:, 1].max()], 0, k.height - 1)
    return [int(math.floor(top)), int(math.floor(left)), int(math.ceil(bottom)), int(math.ceil(right))]


def _in_frame(uv: np.ndarray, margin: float) -> bool:
    k = VKITTI_INTRINSICS
    return bool(margin - 0.5 <= uv[0] <= k.width - 0.5 - margin and margin - 0.5 <= uv[1] <= k.height - 0.5 - margin)


def _separated(uv: np.ndarray, visible: np.ndarray, i: int) -> bool:
    """Whether object ``i``'s projected centre is unambiguous: no other visible object within 12 px."""
    others = visible.copy()
    others[i] = False
    return bool(not others.any() or np.linalg.norm(uv[others] - uv[i], axis=1).min() > _MIN_SEPARATION)


@dataclass(frozen=True)
class OccluderCandidates:
    """A frame's candidate occluder-removed pairs (:func:`occluder_candidates`).

    Attributes:
        pairs: ``(occluder index, hidden car index)`` per pair, in hidden-car then occluder order.
        hidden: how many partly hidden cars the frame has (each may have no occluder to delete).
    """

    pairs: tuple[tuple[int, int], ...]
    hidden: int


def occluder_candidates(objects: FrameObjects, stats: ObjectStats, intrinsics: Intrinsics,
                        max_visible_fraction: float = MAX_HIDDEN_FRACTION) -> OccluderCandidates:
    """Every pair of a frame that an "occluder removed" edit may delete the first car of, to show the second whole.

    A hidden car has at most ``max_visible_fraction`` of its in-frame pixels visible, enough pixels to matter
    (:func:`hidden_min_pixels`), little truncation and lies beyond 3 m; its occluder is a visible car nearer the
    camera whose 2D box overlaps the hidden one's, with an unambiguous, in-frame projected centre (the ``from``
    point that picks it), also beyond 3 m. Whether deleting it reveals enough is the caller's test (a render).
    """
    uv = project_full(objects.center)
    visible = stats.visible > 0
    hidden = np.flatnonzero(visible & (stats.visible >= hidden_min_pixels(intrinsics))
                            & (stats.visible_fraction <= max_visible_fraction)
                            & (stats.truncr <= 0.3) & (objects.center[:, 2] > 3.0))
    box, z = stats.box, objects.center[:, 2]
    pairs = []
    for j in hidden:
        overlap = ((box[:, 0] <= box[j, 2]) & (box[j, 0] <= box[:, 2]) & (box[:, 1] <= box[j, 3])
                   & (box[j, 1] <= box[:, 3]))
        for i in np.flatnonzero(visible & overlap & (z < z[j])):
            if i != j and _separated(uv, visible, int(i)) and _in_frame(uv[i], 0.0) and z[i] > 3.0:
                pairs.append((int(i), int(j)))
    return OccluderCandidates(tuple(pairs), len(hidden))


def hidden_min_pixels(intrinsics: Intrinsics) -> int:
    """Visible pixels a partly hidden car needs for an occluder-removed pair: 0.1 % of the frame, at least 20."""
    return max(20, int(0.001 * intrinsics.width * intrinsics.height))


def remove_occluder(objects: FrameObjects, occluder: int, hidden: int
                    ) -> tuple[FrameObjects, list[BenchmarkOperation], int, int]:
    """The occluder-removed edit of pair ``(occluder, hidden)``: ``(edited objects, [delete op], the hidden car's
    index in the source objects, in the edited ones)``."""
    uv = project_full(objects.center[occluder][None])[0]
    keep = np.arange(len(objects)) != occluder
    op = BenchmarkOperation.delete((round(float(uv[0]), 1), round(float(uv[1]), 1)))
    return objects.subset(keep), [op], hidden, int(keep[:hidden].sum())


def sample_edit(
    rng: np.random.Generator,
    world: World,
    objects: FrameObjects,
    stats: ObjectStats,
    world_to_cam: np.ndarray,
    intrinsics: Intrinsics,
    max_operations: int = 3,
    delete_share: float = DEFAULT_DELETE_SHARE,
) -> tuple[FrameObjects, list[BenchmarkOperation], np.ndarray]:
    """Edit the cars of a source frame; returns the target frame's cars and the operations.

    Args:
        rng: the pair's generator.
        world: the world (car dimensions, road extent).
        objects, stats: the source frame's cars and their statistics.
        world_to_cam: ``(4, 4)`` source (and target) extrinsics.
        intrinsics: working-size intrinsics (only for the minimum visible size).
        max_operations: at most this many operations (fewer if fewer cars qualify).
        delete_share: the chance that each chosen car is deleted (one uniform draw per car, as before the option:
            the default draws the same pairs).

    Returns:
        The edited :class:`FrameObjects` (deleted cars removed), the operations (empty when no
        car qualifies) and a ``(N',)`` bool mask of the edited objects that were modified.
    """
    dims_all = world.cars.dims[objects.track]
    center = objects.center.copy()
    ry = objects.ry.copy()
    uv = project_full(center)
    min_pixels = max(40, int(0.002 * intrinsics.width * intrinsics.height))
    visible = stats.visible > 0
    eligible = []
    for i in range(len(objects)):
        separated = _separated(uv, visible, i)
        if (
            stats.visible[i] >= min_pixels
            and stats.visible_fraction[i] >= 0.5
            and stats.truncr[i] <= 0.3
            and center[i, 2] > 3.0
            and separated
            and _in_frame(uv[i], 0.0)
        ):
            eligible.append(i)
    if not eligible:
        return objects, [], np.zeros(len(objects), dtype=bool)
    count = int(rng.integers(1, min(max_operations, len(eligible)) + 1))
    chosen = rng.choice(np.array(eligible), size=count, replace=False)
    cam_to_world = np.linalg.inv(world_to_cam)
    road = world.road
    alive = np.ones(len(objects), dtype=bool)
    modified = np.zeros(len(objects), dtype=bool)
    operations: list[BenchmarkOperation] = []
    for i in sorted(int(c) for c in chosen):
        from_uv = (round(float(uv[i, 0]), 1), round(float(uv[i, 1]), 1))
        if rng.uniform() < delete_share:
            alive[i] = False
            operations.append(BenchmarkOperation.delete(from_uv))
            continue
        dims = dims_all[i]
        rotate_only = rng.uniform() < 0.2
        for _ in range(_MAX_TRIES):
            draw = rng.uniform()
            if rotate_only:
                d_ry = round(float(rng.choice([-1, 1]) * rng.uniform(0.2, math.pi)), 3)
            else:
                d_ry = (
                    round(float(rng.uniform(-0.3, 0.3)), 3)
                    if draw < 0.5
                    else (round(float(rng.uniform(-math.pi, math.pi)), 3) if draw < 0.7 else 0.0)
                )
            new_ry = float(np.remainder(ry[i] + d_ry + math.pi, 2 * math.pi) - math.pi)
            new_center = center[i].copy()
            if not rotate_only:
                bottom_w = cam_to_world[:3, :3] @ (center[i] + [0.0, dims[1] / 2, 0.0]) + cam_to_world[:3, 3]
                bottom_w += [rng.uniform(-2.5, 2.5), 0.0, rng.uniform(-8.0, 8.0)]
                half = dims[2] / 2 + 0.2
                if not road.kerb_left + half <= bottom_w[0] <= road.kerb_right - half:
                    continue
                new_center = world_to_cam[:3, :3] @ bottom_w + world_to_cam[:3, 3] - [0.0, dims[1] / 2, 0.0]
                if not 5.0 + dims[0] / 2 <= new_center[2] <= 60.0:
                    continue
            new_uv = project_full(new_center[None])[0]
            if not _in_frame(new_uv, 20.0):
                continue
            rect = _footprint(new_center, dims, new_ry)
            others = [j for j in range(len(objects)) if j != i and alive[j]]
            if any(footprints_overlap(rect, _footprint(center[j], dims_all[j], ry[j])) for j in others):
                continue
            break
        else:
            if rotate_only:
                continue  # no collision-free rotation found: leave this car alone
            rotate_only, new_center = True, center[i].copy()  # no free spot to move to: rotate in place
            for _ in range(_MAX_TRIES):
                d_ry = round(float(rng.choice([-1, 1]) * rng.uniform(0.2, math.pi)), 3)
                new_ry = float(np.remainder(ry[i] + d_ry + math.pi, 2 * math.pi) - math.pi)
                rect = _footprint(new_center, dims, new_ry)
                others = [j for j in range(len(objects)) if j != i and alive[j]]
                if not any(footprints_overlap(rect, _footprint(center[j], dims_all[j], ry[j])) for j in others):
                    break
            else:
                continue
        if rotate_only:
            operations.append(BenchmarkOperation.modify(from_uv, None, 1.0, d_ry))
        else:
            zoom = round(float(np.linalg.norm(center[i]) / np.linalg.norm(new_center)), 3)
            to_uv = (round(float(new_uv[0]), 1), round(float(new_uv[1]), 1))
            roi = tuple(_roi(new_center, dims, new_ry))
            operations.append(BenchmarkOperation.modify(from_uv, to_uv, zoom, d_ry, roi))
        center[i], ry[i] = new_center, new_ry
        modified[i] = True
    edited = FrameObjects(objects.track.copy(), center, ry, objects.moving.copy())
    return edited.subset(alive), operations, modified[alive]
