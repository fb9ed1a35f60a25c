"""Writers of tiny, deterministic datasets in the exact on-disk formats the readers parse.

Each writer builds a small street scene (stuff bands, a few Car/Van tracks whose 2D
boxes are the projections of their 3D boxes under the docs/ARCHITECTURE.md conventions),
encodes it exactly as the real dataset does (colour-coded PNGs with their tables,
centimetre depth PNGs, KITTI-like text annotations) and returns the ground truth it
encoded as :class:`FixtureFrame` objects, so tests can compare what a reader
decodes with what was written. Object masks are car-like silhouettes in the pixel rectangles of the
projected boxes (the top :data:`_CABIN_ROWS` of the rows cover only the middle :data:`_CABIN_COLS` of the
columns, so an unoccluded car covers about 84 % of its box, as real cars cover about 75-85 %), painted far to
near. As in the real files, ``occupr`` is visible pixels / box area and the ``occluded`` flag (Virtual KITTI 1)
follows the share of the object's in-frame silhouette that is visible.

Used by the reader tests and as format templates for the synthetic generator. The Cityscapes writer is
:mod:`sdn3d.data.fixtures_cityscapes`.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
import shutil
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.data.imageio import image_size
from sdn3d.data.records import ObjectAnnotation
from sdn3d.data.vkitti1 import ENCODING_HEADER, MOTGT_HEADER, PUBLISHED_EXTRINSICS_HEADER
from sdn3d.data.vkitti2 import (
    BBOX_HEADER,
    COLORS_HEADER,
    EXTRINSIC_HEADER,
    INFO_HEADER,
    INTRINSIC_HEADER,
    POSE_HEADER,
)
from sdn3d.io import write_png_atomic
from sdn3d.labels import IGNORE_INDEX, INSTANCE_DIVISOR, VKITTI_CLASS_INDEX, VKITTI_CLASSES
from sdn3d.math3d.camera import VKITTI_INTRINSICS, Intrinsics

__all__ = [
    "FixtureFrame",
    "VKITTI2_COLORS",
    "VKITTI2_BASELINE",
    "write_vkitti1_fixture",
    "write_vkitti2_fixture",
]

#: Virtual KITTI 2 ``colors.txt`` (differs from VKITTI 1 in GuardRail and in class colours for Car/Van).
VKITTI2_COLORS: tuple[tuple[str, tuple[int, int, int]], ...] = (
    *((c.name, (250, 100, 255) if c.name == "GuardRail" else c.color) for c in VKITTI_CLASSES),
    ("Undefined", (0, 0, 0)),
)
#: Distance of Camera_1 to the right of Camera_0 in Virtual KITTI 2, metres.
VKITTI2_BASELINE = 0.532725
_CAMERA_HEIGHT = 1.65  # y of the ground plane in the camera frame (metres, y down)
_FAR_CM = 65535


@dataclass(frozen=True, eq=False)
class FixtureFrame:
    """Ground truth of one written frame (arrays are what the reader should return)."""

    world: str
    variation: str
    frame: int
    camera: str | None
    intrinsics: Intrinsics
    semantic: np.ndarray  # (H, W) int64
    instances: np.ndarray  # (H, W) int64
    depth: np.ndarray  # (H, W) float32 metres, as quantised on disk
    objects: tuple[ObjectAnnotation, ...]
    extrinsics: np.ndarray | None  # (4, 4) world->camera


@dataclass(frozen=True)
class _Track:
    tid: int
    label: str
    dims: tuple[float, float, float]  # l, h, w
    x: float
    z: float
    dz: float  # metres per frame
    ry: float
    model: str
    color: str


# At frame 43 (43 % 8 == 3) tracks 0 and 1 sit roughly where the two cars of the reference
# frame 0006/30-deg-right/00043 are (track 0's centre projects near (552, 251), the point the
# shipped edit example picks); the van is partly hidden by track 1, track 5 cut by the border.
_TRACKS = (
    _Track(0, "Car", (3.9, 1.5, 1.75), -0.96, 11.7, -0.5, -1.5, "Hatchback", "Red"),
    _Track(1, "Car", (3.9, 1.45, 1.75), 3.03, 10.7, 0.3, -1.6, "Hatchback", "Black"),
    _Track(3, "Van", (4.9, 2.0, 1.95), 4.5, 22.0, 0.0, -1.57, "MPV", "White"),
    _Track(5, "Car", (4.5, 1.5, 1.85), 7.5, 11.0, 0.0, 0.2, "SUV", "Black"),
)
_UNSEEN_TIDS = (7, 8)  # listed in tables but never visible, as in the real files


def _r6(value: float) -> float:
    return float(f"{value:.6f}")


def _roty(ry: float) -> np.ndarray:
    c, s = math.cos(ry), math.sin(ry)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _stuff(width: int, height: int, horizon: int) -> np.ndarray:
    """Class-name index map of the static background (every VKITTI stuff class appears)."""
    ids = VKITTI_CLASS_INDEX
    sem = np.full((height, width), ids["Sky"], dtype=np.int64)

    def rows(a: float) -> int:
        return int(a * height)

    def cols(a: float) -> int:
        return int(a * width)

    thick = max(1, width // 200)
    sem[rows(0.3) : horizon, :] = ids["Building"]
    sem[rows(0.3) : horizon, cols(0.4) : cols(0.7)] = ids["Tree"]
    sem[rows(0.4) : horizon, cols(0.7) :] = ids["Vegetation"]
    sem[rows(0.38) : horizon, cols(0.02) : cols(0.1)] = ids["Truck"]
    sem[horizon:, :] = ids["Road"]
    sem[horizon:, : cols(0.12)] = ids["Terrain"]
    sem[horizon:, cols(0.88) :] = ids["Terrain"]
    sem[horizon : horizon + max(1, height // 40), cols(0.12) : cols(0.3)] = ids["GuardRail"]
    sem[rows(0.25) : horizon, cols(0.85) : cols(0.85) + thick] = ids["Pole"]
    sem[rows(0.2) : rows(0.25), cols(0.85) - thick : cols(0.85) + 2 * thick] = ids["TrafficSign"]
    sem[rows(0.2) : rows(0.25), cols(0.6) : cols(0.6) + 2 * thick] = ids["TrafficLight"]
    sem[horizon - max(1, height // 30) : horizon, cols(0.32) : cols(0.36)] = ids["Misc"]
    return sem


#: Car silhouettes: the top ``_CABIN_ROWS`` of a box's rows cover only its middle ``_CABIN_COLS`` columns.
_CABIN_ROWS, _CABIN_COLS = 0.4, 0.6


def _silhouette(j0: int, j1: int, i0: int, i1: int, width: int, height: int) -> np.ndarray:
    """``(height, width)`` bool car silhouette of the full (unclipped) inclusive pixel box ``j0..j1 x i0..i1``."""
    cols = np.arange(width)[None, :]
    rows = np.arange(height)[:, None]
    in_box = (cols >= j0) & (cols <= j1) & (rows >= i0) & (rows <= i1)
    margin = math.floor((j1 - j0 + 1) * (1.0 - _CABIN_COLS) / 2)
    cabin = rows < i0 + math.floor((i1 - i0 + 1) * _CABIN_ROWS)
    return in_box & (~cabin | ((cols >= j0 + margin) & (cols <= j1 - margin)))


def _silhouette_area(j0: int, j1: int, i0: int, i1: int) -> int:
    """Pixel count of the whole silhouette of :func:`_silhouette` (in and out of the frame)."""
    box_w, box_h = j1 - j0 + 1, i1 - i0 + 1
    margin = math.floor(box_w * (1.0 - _CABIN_COLS) / 2)
    return box_w * box_h - math.floor(box_h * _CABIN_ROWS) * 2 * margin


def _scene(intr: Intrinsics, frame: int, shift: float = 0.0):
    """Semantic ids, per-pixel track ids (-1 none), depth (m) and object rows for one frame.

    ``shift`` moves the camera ``shift`` metres to the right (Camera_1 of VKITTI 2).
    """
    width, height = intr.width, intr.height
    horizon = math.floor(intr.cy) + 1  # first row strictly below the horizon
    sem = _stuff(width, height, horizon)
    depth = np.full((height, width), _FAR_CM / 100.0)
    rows = np.arange(height, dtype=np.float64)[:, None]
    ground = _CAMERA_HEIGHT * intr.fy / np.maximum(rows - intr.cy, 1e-6)
    depth = np.where(rows >= horizon, np.minimum(ground, 655.0), depth)
    depth[(sem != VKITTI_CLASS_INDEX["Sky"]) & (rows < horizon)] = 60.0
    tids = np.full((height, width), -1, dtype=np.int64)
    corners = np.array(list(itertools.product((-0.5, 0.5), repeat=3)))
    placed = []
    for t in _TRACKS:
        l, h, w = t.dims
        # Motion repeats every 8 frames so that any frame index keeps the tracks in front.
        x, y, z = t.x - shift, _CAMERA_HEIGHT, t.z + t.dz * (frame % 8)
        pts = (_roty(t.ry) @ (corners * [l, h, w]).T).T + [x, y - h / 2, z]
        if pts[:, 2].min() < 1.0:
            continue
        u = intr.fx * pts[:, 0] / pts[:, 2] + intr.cx
        v = intr.fy * pts[:, 1] / pts[:, 2] + intr.cy
        j0, j1, i0, i1 = math.ceil(u.min()), math.floor(u.max()), math.ceil(v.min()), math.floor(v.max())
        c0, c1, r0, r1 = max(j0, 0), min(j1, width - 1), max(i0, 0), min(i1, height - 1)
        if c1 < c0 or r1 < r0:
            continue
        mask = _silhouette(j0, j1, i0, i1, width, height)
        truncr = 1.0 - int(mask.sum()) / _silhouette_area(j0, j1, i0, i1)
        placed.append((z, t, (x, y, z), (c0, r0, c1, r1), truncr, mask))
    objects = []
    for z, t, _, _, _, mask in sorted(placed, key=lambda p: -p[0]):  # far to near
        tids[mask] = t.tid
        sem[mask] = VKITTI_CLASS_INDEX[t.label]
        depth[mask] = z
    for _, t, loc, (c0, r0, c1, r1), truncr, mask in placed:
        visible = int((tids == t.tid).sum())
        if visible == 0:
            continue
        alpha = math.remainder(t.ry - math.atan2(loc[0], loc[2]), 2 * math.pi)
        occupr = visible / ((c1 - c0 + 1) * (r1 - r0 + 1))  # the real files' occupr: visible / box area
        objects.append((t, loc, (c0, r0, c1, r1), truncr, occupr, alpha, visible, visible / int(mask.sum())))
    depth_cm = np.clip(np.round(depth * 100.0), 0, _FAR_CM).astype(np.uint16)
    return sem, tids, depth_cm, objects


def _annotation(t: _Track, loc, box, truncr, occupr, alpha, visible, visible_fraction,
                with_flags: bool) -> ObjectAnnotation:
    """One object's annotation; the ``occluded`` flag follows ``visible_fraction`` (visible / in-frame
    silhouette pixels), not ``occupr`` (visible / box area)."""
    truncated = 0 if truncr < 0.15 else (1 if truncr < 0.5 else 2)
    occluded = 0 if visible_fraction > 0.9 else (1 if visible_fraction > 0.4 else 2)
    dont_care = with_flags and 2 in (truncated, occluded)
    return ObjectAnnotation(
        track_id=t.tid,
        label="DontCare" if dont_care else t.label,
        box2d=tuple(float(b) for b in box),
        dims=tuple(_r6(d) for d in t.dims),
        location=tuple(_r6(c) for c in loc),
        ry=_r6(t.ry),
        alpha=_r6(alpha),
        truncr=_r6(truncr),
        occupr=_r6(occupr),
        truncated=truncated if with_flags else None,
        occluded=occluded if with_flags else None,
        orig_label=t.label if with_flags else None,
        moving=t.dz != 0.0,
        model=t.model,
        color=t.color,
        num_pixels=None if with_flags else visible,
    )


def _extrinsics(frame: int, shift: float = 0.0) -> np.ndarray:
    """World->camera: the camera drives 0.8 m/frame along world z, turning 0.01 rad/frame."""
    yaw = 0.01 * frame
    rotation = _roty(yaw)
    centre = np.array([shift * math.cos(yaw), 0.0, 0.8 * frame - shift * math.sin(yaw)])
    matrix = np.eye(4)
    matrix[:3, :3] = rotation.T
    matrix[:3, 3] = -rotation.T @ centre
    return np.array([[float(f"{v:.9g}") for v in row] for row in matrix])


def _matrix_text(matrix: np.ndarray) -> str:
    return " ".join(f"{v:.9g}" for v in matrix.reshape(-1))


def _rgb_from(sem: np.ndarray, palette: dict[int, tuple[int, int, int]]) -> np.ndarray:
    lut = np.zeros((max(palette) + 1, 3), dtype=np.int64)
    for class_id, color in palette.items():
        lut[class_id] = color
    shade = (np.indices(sem.shape).sum(0) % 16)[..., None]
    return (lut[sem] * 0.7 + shade * 2).astype(np.uint8)


def _instances(sem: np.ndarray, tids: np.ndarray) -> np.ndarray:
    """VKITTI instance ids ``class_id * 1000 + tid + 1`` (0 where ``tids`` is -1)."""
    return np.where(tids >= 0, sem * INSTANCE_DIVISOR + tids + 1, 0)


def _rgb_text(color: Sequence[int]) -> str:
    return " ".join(str(int(c)) for c in color)


def _track_color(tid: int) -> tuple[int, int, int]:
    return (200 - (tid * 37) % 100, 100 + (tid * 53) % 150, 35 + (tid * 71) % 200)


def _write_table(path: Path, header: Sequence[str], lines: Sequence[str]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join([" ".join(header), *lines]) + "\n", encoding="utf-8")


def _vkitti_intrinsics(size: tuple[int, int]) -> Intrinsics:
    if tuple(size) == (VKITTI_INTRINSICS.width, VKITTI_INTRINSICS.height):
        return VKITTI_INTRINSICS
    return VKITTI_INTRINSICS.resized(*size)


def write_vkitti1_fixture(
    root: str | os.PathLike,
    world: str = "0001",
    variation: str = "clone",
    frames: Sequence[int] = (0, 1, 2),
    size: tuple[int, int] = (64, 32),
    rgb_image: str | os.PathLike | None = None,
) -> list[FixtureFrame]:
    """Write one Virtual KITTI 1.3.1 sequence (rgb, scenegt + encoding, depthgt, motgt, extrinsicsgt).

    Args:
        root: dataset root (created); other sequences already there are kept.
        world, variation, frames: what to write.
        size: ``(width, height)``; ignored when ``rgb_image`` is given.
        rgb_image: a real RGB PNG copied byte-for-byte as every frame's image (its size
            is used); otherwise a synthetic colour rendering of the labels is written.
    """
    root = Path(root)
    if rgb_image is not None:
        size = image_size(rgb_image)
    intr = _vkitti_intrinsics(size)
    seq = f"{world}/{variation}"
    palette = {c.id: c.color for c in VKITTI_CLASSES}
    enc = [f"{c.name} {_rgb_text(c.color)}" for c in VKITTI_CLASSES if not c.has_instances]
    tracks = sorted([(t.tid, t.label) for t in _TRACKS] + [(tid, "Car") for tid in _UNSEEN_TIDS])
    enc += [f"{label}:{tid} {_rgb_text(_track_color(tid))}" for tid, label in tracks]
    _write_table(root / "vkitti_1.3.1_scenegt" / f"{world}_{variation}_scenegt_rgb_encoding.txt",
                 ENCODING_HEADER, enc)  # fmt: skip
    mot_lines, ext_lines, out = [], [], []
    for frame in frames:
        sem, tids, depth_cm, objs = _scene(intr, frame)
        name = f"{frame:05d}.png"
        if rgb_image is not None:
            (root / "vkitti_1.3.1_rgb" / seq).mkdir(parents=True, exist_ok=True)
            shutil.copyfile(rgb_image, root / "vkitti_1.3.1_rgb" / seq / name)
        else:
            write_png_atomic(root / "vkitti_1.3.1_rgb" / seq / name, _rgb_from(sem, palette))
        scene_rgb = np.array([c.color for c in VKITTI_CLASSES], dtype=np.uint8)[sem]
        for tid, _ in tracks:
            scene_rgb[tids == tid] = _track_color(tid)
        write_png_atomic(root / "vkitti_1.3.1_scenegt" / seq / name, scene_rgb)
        write_png_atomic(root / "vkitti_1.3.1_depthgt" / seq / name, depth_cm)
        annotations = tuple(_annotation(*o, with_flags=True) for o in objs)
        for a in annotations:
            l, t, r, b = (int(v) for v in a.box2d)
            mot_lines.append(
                f"{frame} {a.track_id} {a.label} {a.truncated} {a.occluded} {a.alpha:.6f} {l} {t} {r} {b} "
                f"{a.dims[2]:.6f} {a.dims[1]:.6f} {a.dims[0]:.6f} "
                + " ".join(f"{v:.6f}" for v in (*a.location, a.ry, a.rx, a.rz, a.truncr, a.occupr))
                + f" {a.orig_label} {int(a.moving)} {a.model} {a.color}"
            )
        extr = _extrinsics(frame)
        ext_lines.append(f"{frame} {_matrix_text(extr)}")
        instances, depth = _instances(sem, tids), depth_cm.astype(np.float32) / np.float32(100.0)
        out.append(FixtureFrame(world, variation, frame, None, intr, sem, instances, depth, annotations,
                                extr))
    seq_txt = f"{world}_{variation}.txt"
    _write_table(root / "vkitti_1.3.1_motgt" / seq_txt, MOTGT_HEADER, mot_lines)
    _write_table(root / "vkitti_1.3.1_extrinsicsgt" / seq_txt, PUBLISHED_EXTRINSICS_HEADER, ext_lines)
    return out


def _box_occupancy(annotation: ObjectAnnotation) -> ObjectAnnotation:
    """VKITTI 2 ``occupancy_ratio``: visible pixels / ``((r - l) * (b - t))`` (fits bbox.txt sample rows)."""
    left, top, right, bottom = annotation.box2d
    area = max((right - left) * (bottom - top), 1.0)  # guard against /0 only; no such box at fixture sizes
    return dataclasses.replace(annotation, occupr=_r6(annotation.num_pixels / area))


def write_vkitti2_fixture(
    root: str | os.PathLike,
    scene: str = "Scene01",
    variation: str = "clone",
    frames: Sequence[int] = (0, 1),
    size: tuple[int, int] = (64, 32),
    instance_mode: str = "P",
) -> list[FixtureFrame]:
    """Write one Virtual KITTI 2.0.3 sequence for both cameras (jpg rgb, classgt, instancegt,
    depth, colors/bbox/pose/info/intrinsic/extrinsic text files).

    ``instance_mode``: PNG mode of ``instancegt`` (values ``trackID + 1``): ``'P'`` (8-bit indexed, as
    shipped), ``'L'`` or ``'I;16'``. ``occupancy_ratio`` is ``number_pixels / ((r - l) * (b - t))`` as in
    the real files (about 0.9 for an unoccluded fixture car: its silhouette over the exclusive box).
    A 2x2 ``Undefined`` patch sits in the top-left corner.
    Returns Camera_0 frames then Camera_1 frames.
    """
    if instance_mode not in ("L", "P", "I;16"):
        raise ValueError(f"instance_mode must be 'L', 'P' or 'I;16', got {instance_mode!r}")
    seq = Path(root) / scene / variation
    intr = _vkitti_intrinsics(size)
    palette = {VKITTI_CLASS_INDEX.get(n, IGNORE_INDEX): c for n, c in VKITTI2_COLORS}
    _write_table(seq / "colors.txt", COLORS_HEADER, [f"{n} {_rgb_text(c)}" for n, c in VKITTI2_COLORS])
    info = [(t.tid, t.label, t.model, t.color) for t in _TRACKS]
    info = sorted(info + [(i, "Car", "Sedan2Door", "Blue") for i in _UNSEEN_TIDS])
    _write_table(seq / "info.txt", INFO_HEADER, [" ".join(map(str, row)) for row in info])
    bbox, pose, k_lines, e_lines, out = [], [], [], [], []
    for cam in (0, 1):
        camera = f"Camera_{cam}"
        for frame in frames:
            sem, tids, depth_cm, objs = _scene(intr, frame, shift=cam * VKITTI2_BASELINE)
            sem[:2, :2], tids[:2, :2] = IGNORE_INDEX, -1
            frames_dir = seq / "frames"
            rgb = _rgb_from(sem, palette)
            (frames_dir / "rgb" / camera).mkdir(parents=True, exist_ok=True)
            Image.fromarray(rgb).save(frames_dir / "rgb" / camera / f"rgb_{frame:05d}.jpg", quality=95)
            lut = np.zeros((IGNORE_INDEX + 1, 3), dtype=np.uint8)
            for class_id, color in palette.items():
                lut[class_id] = color
            write_png_atomic(frames_dir / "classSegmentation" / camera / f"classgt_{frame:05d}.png", lut[sem])
            values = (tids + 1).astype(np.uint16 if instance_mode == "I;16" else np.uint8)
            image = Image.fromarray(values)
            if instance_mode == "P":
                image = image.convert("P")
                image.putpalette([v for i in range(256) for v in _track_color(i)])
            path = frames_dir / "instanceSegmentation" / camera / f"instancegt_{frame:05d}.png"
            path.parent.mkdir(parents=True, exist_ok=True)
            image.save(path)
            write_png_atomic(frames_dir / "depth" / camera / f"depth_{frame:05d}.png", depth_cm)
            annotations = tuple(_box_occupancy(_annotation(*o, with_flags=False)) for o in objs)
            extr = _extrinsics(frame, shift=cam * VKITTI2_BASELINE)
            for a in annotations:
                l, t, r, b = (int(v) for v in a.box2d)
                bbox.append(f"{frame} {cam} {a.track_id} {l} {r} {t} {b} {a.num_pixels} {a.truncr:.6f} "
                            f"{a.occupr:.6f} {a.moving}")  # fmt: skip
                world_xyz = np.linalg.inv(extr) @ np.array([*a.location, 1.0])
                values = (a.alpha, a.dims[2], a.dims[1], a.dims[0], *world_xyz[:3], a.ry - 0.01 * frame,
                          0.0, 0.0, *a.location, a.ry, a.rx, a.rz)  # fmt: skip
                pose.append(f"{frame} {cam} {a.track_id} " + " ".join(f"{v:.6f}" for v in values))
            k_lines.append(f"{frame} {cam} {intr.fx:.9g} {intr.fy:.9g} {intr.cx:.9g} {intr.cy:.9g}")
            e_lines.append(f"{frame} {cam} {_matrix_text(extr)}")
            instances, depth = _instances(sem, tids), depth_cm.astype(np.float32) / np.float32(100.0)
            k = Intrinsics(*(float(f"{v:.9g}") for v in (intr.fx, intr.fy, intr.cx, intr.cy)), *size)
            out.append(FixtureFrame(scene, variation, frame, camera, k, sem, instances, depth, annotations,
                                    extr))
    _write_table(seq / "bbox.txt", BBOX_HEADER, bbox)
    _write_table(seq / "pose.txt", POSE_HEADER, pose)
    _write_table(seq / "intrinsic.txt", INTRINSIC_HEADER, k_lines)
    _write_table(seq / "extrinsic.txt", EXTRINSIC_HEADER, e_lines)
    return out
