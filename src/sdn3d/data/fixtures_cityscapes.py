"""Cityscapes fixture writer (split from :mod:`sdn3d.data.fixtures`, which re-exports it).

Writes a tiny dataset in Cityscapes' exact layout (``leftImg8bit``, ``gtFine`` label / instance ids,
``camera`` JSON) and returns the ground truth as :class:`~sdn3d.data.fixtures.FixtureFrame` objects.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from sdn3d.data.fixtures import FixtureFrame
from sdn3d.io import write_png_atomic
from sdn3d.labels import CITYSCAPES_LABELS, IGNORE_INDEX, INSTANCE_DIVISOR, LABEL_TO_TRAIN
from sdn3d.math3d.camera import Intrinsics

__all__ = ["CITYSCAPES_FIXTURE_FRAMES", "write_cityscapes_fixture"]


#: Default Cityscapes fixture frames: split -> (city, sequence, frame).
CITYSCAPES_FIXTURE_FRAMES = {
    "train": (("aachen", 0, 19), ("aachen", 1, 19), ("aachen", 2, 19)),
    "val": (("frankfurt", 0, 294),),
}
_CS_EXTRINSIC = {"baseline": 0.209313, "pitch": 0.038, "roll": 0.0, "x": 1.7, "y": 0.1, "yaw": -0.0195}
_CS_EXTRINSIC["z"] = 1.22


def _cityscapes_labels(width: int, height: int, shift: int) -> tuple[np.ndarray, np.ndarray]:
    """(labelIds, instanceIds) of one frame; instance ids follow the gtFine convention."""
    lab = np.full((height, width), 23, dtype=np.int64)  # sky

    def box(a: np.ndarray, t: float, b: float, l: float, r: float, value: int, dx: int = 0) -> None:
        a[int(t * height) : int(b * height), int(l * width) + dx : int(r * width) + dx] = value

    box(lab, 0.3, 0.5, 0.0, 1.0, 11)  # building
    box(lab, 0.3, 0.5, 0.6, 1.0, 21)  # vegetation
    box(lab, 0.5, 1.0, 0.0, 1.0, 7)  # road
    box(lab, 0.5, 1.0, 0.0, 0.15, 8)  # sidewalk
    box(lab, 0.2, 0.5, 0.5, 0.52, 17)  # pole
    box(lab, 0.15, 0.2, 0.48, 0.55, 20)  # traffic sign
    box(lab, 0.85, 0.95, 0.8, 0.9, 9)  # parking
    inst = lab.copy()
    for t, b, l, r, label_id, instance_id, dx in (
        (0.5, 0.75, 0.2, 0.4, 26, 26000, shift),  # car k=0
        (0.55, 0.8, 0.45, 0.6, 26, 26001, 0),  # car k=1
        (0.4, 0.7, 0.65, 0.7, 24, 24000, 0),  # person k=0
        (0.5, 0.6, 0.85, 0.95, 26, 26, 0),  # crowd of cars: plain label id
        (0.5, 0.6, 0.72, 0.8, 29, 29000, 0),  # caravan (no train id)
    ):
        box(lab, t, b, l, r, label_id, dx)
        box(inst, t, b, l, r, instance_id, dx)
    lab[int(0.95 * height) :, :] = 1  # ego vehicle
    inst[int(0.95 * height) :, :] = 1
    return lab, inst


def write_cityscapes_fixture(
    root: str | os.PathLike,
    frames: dict[str, Sequence[tuple[str, int, int]]] | None = None,
    size: tuple[int, int] = (64, 32),
    disparity: bool = True,
) -> list[FixtureFrame]:
    """Write Cityscapes frames: leftImg8bit, gtFine labelIds/instanceIds/color, camera json
    and (optionally) disparity. ``frames`` maps split -> ``(city, sequence, frame)``;
    default :data:`CITYSCAPES_FIXTURE_FRAMES`. FixtureFrame.semantic holds train ids."""
    root = Path(root)
    width, height = size
    sx, sy = width / 2048, height / 1024
    intrinsic = {"fx": 2262.52 * sx, "fy": 2265.3017905988 * sy, "u0": 1096.98 * sx, "v0": 513.137 * sy}
    colors = np.zeros((256, 3), dtype=np.uint8)
    for name, label_id, _train, _inst, color in CITYSCAPES_LABELS:
        del name
        colors[label_id] = color
    out = []
    for split, items in (frames or CITYSCAPES_FIXTURE_FRAMES).items():
        for index, (city, sequence, frame) in enumerate(items):
            stem = f"{city}_{sequence:06d}_{frame:06d}"
            lab, inst = _cityscapes_labels(width, height, shift=index % 3)
            write_png_atomic(root / "leftImg8bit" / split / city / f"{stem}_leftImg8bit.png", colors[lab])
            gt = root / "gtFine" / split / city
            write_png_atomic(gt / f"{stem}_gtFine_labelIds.png", lab.astype(np.uint8))
            write_png_atomic(gt / f"{stem}_gtFine_instanceIds.png", inst.astype(np.uint16))
            write_png_atomic(gt / f"{stem}_gtFine_color.png", colors[lab])
            camera = root / "camera" / split / city / f"{stem}_camera.json"
            camera.parent.mkdir(parents=True, exist_ok=True)
            camera.write_text(json.dumps({"extrinsic": _CS_EXTRINSIC, "intrinsic": intrinsic}, indent=4))
            rows = np.arange(height, dtype=np.float64)[:, None].repeat(width, 1)
            depth = np.zeros((height, width), dtype=np.float32)
            if disparity:
                below = rows > intrinsic["v0"] + 1
                z = np.where(below, _CS_EXTRINSIC["z"] * intrinsic["fy"] / (rows - intrinsic["v0"]), 0.0)
                d = np.where(z > 0, _CS_EXTRINSIC["baseline"] * intrinsic["fx"] / np.maximum(z, 1e-9), 0.0)
                p = np.where(z > 0, np.clip(np.round(d * 256.0) + 1, 2, 65535), 0).astype(np.uint16)
                write_png_atomic(root / "disparity" / split / city / f"{stem}_disparity.png", p)
                raw = p.astype(np.float32)
                valid = raw > 1.0
                depth[valid] = _CS_EXTRINSIC["baseline"] * intrinsic["fx"] / ((raw[valid] - 1.0) / 256.0)
            train = LABEL_TO_TRAIN[np.where(inst >= INSTANCE_DIVISOR, inst // INSTANCE_DIVISOR, inst)]
            keep = (inst >= INSTANCE_DIVISOR) & (train != IGNORE_INDEX)
            instances = np.where(keep, train * INSTANCE_DIVISOR + inst % INSTANCE_DIVISOR, 0)
            k = Intrinsics(intrinsic["fx"], intrinsic["fy"], intrinsic["u0"], intrinsic["v0"], width, height)
            semantic = LABEL_TO_TRAIN[lab]
            out.append(FixtureFrame(city, split, frame, None, k, semantic, instances, depth, (), None))
    return out
