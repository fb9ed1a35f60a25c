"""Cityscapes reader (fine annotations).

On-disk layout under ``root``::

    leftImg8bit/<split>/<city>/<city>_<seq>_<frame>_leftImg8bit.png       8-bit RGB
    gtFine/<split>/<city>/<city>_<seq>_<frame>_gtFine_labelIds.png        8-bit label ids 0..33
    gtFine/<split>/<city>/<city>_<seq>_<frame>_gtFine_instanceIds.png     16-bit, see below
    camera/<split>/<city>/<city>_<seq>_<frame>_camera.json                intrinsic fx fy u0 v0, extrinsic
    disparity/<split>/<city>/<city>_<seq>_<frame>_disparity.png           16-bit (optional)

Semantic maps are the 19 train ids (0..18) of :data:`CITYSCAPES_LABELS`, 255 ignore.

instanceIds hold ``label_id * 1000 + k`` (k from 0) for individual objects of
classes with instances and the plain label id (< 1000) everywhere else, crowd
regions included. Instance maps keep only values >= 1000 and become
``train_id * 1000 + k``, the file's ``k`` unchanged (train ids of instance classes
are >= 11, so no id is 0); instances of classes without a train id (caravan,
trailer) become 0 like the rest.

Depth comes from the disparity maps when present: ``d = (p - 1) / 256`` for
``p > 0`` and ``z = baseline * fx / d``; invalid pixels (``p == 0``) are 0.

The label table (:data:`sdn3d.labels.CITYSCAPES_LABELS`) lives with the other class lists in
:mod:`sdn3d.labels`.

A city's image size is the one its frames agree on (:func:`~sdn3d.data.imageio.agreed_size`); an
unreadable or odd-sized image, or a missing or broken camera file, stops indexing naming the file, or under
the skip policy (:func:`read_frames` ``skip=``) drops that frame and records it.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections import Counter
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from sdn3d.data.errors import DataFormatError, SkipLog, missing
from sdn3d.data.imageio import image_size, read_index_png, read_rgb, read_uint16_png
from sdn3d.data.records import FrameRecord, check_size
from sdn3d.labels import CITYSCAPES_LABELS, IGNORE_INDEX, INSTANCE_DIVISOR, LABEL_TO_TRAIN
from sdn3d.math3d.camera import CameraPose, Intrinsics

__all__ = [
    "camera_pose",
    "camera_to_vehicle",
    "read_camera",
    "read_frames",
    "load_rgb",
    "load_semantic",
    "load_instances",
    "load_depth",
]

_NUM_LABEL_IDS = len(CITYSCAPES_LABELS)
_NAME = re.compile(r"^(?P<city>.+)_(?P<seq>\d{6})_(?P<frame>\d{6})_leftImg8bit\.png$")


def _rotation(yaw: float, pitch: float, roll: float) -> np.ndarray:
    cy, sy, cp, sp, cr, sr = (math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch),
                              math.cos(roll), math.sin(roll))  # fmt: skip
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


#: ISO 8855 camera axes (x forward, y left, z up) -> KITTI camera axes (x right, y down, z forward).
ISO_TO_KITTI = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])


def camera_to_vehicle(extrinsic: dict) -> np.ndarray:
    """``(4, 4)`` transform from the KITTI-axes camera frame to the vehicle frame.

    Per the Cityscapes calibration notes, the vehicle frame is ISO 8855 (x forward,
    y left, z up); the camera sits at ``(x, y, z)`` in it with orientation
    ``R = Rz(yaw) Ry(pitch) Rx(roll)`` of camera axes that are also x forward, y left,
    z up. The camera's KITTI axes are then ``ISO_TO_KITTI`` applied to those.
    """
    rotation = _rotation(extrinsic["yaw"], extrinsic["pitch"], extrinsic["roll"]) @ ISO_TO_KITTI.T
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = [extrinsic["x"], extrinsic["y"], extrinsic["z"]]
    return transform


def camera_pose(extrinsic: dict) -> CameraPose:
    """The road plane of a ``camera.json`` ``extrinsic``: the camera's height above the ground (``z``: the
    vehicle frame's origin is on the ground below the rear axle) and its ``pitch`` and ``roll`` (radians, the
    conventions of :func:`camera_to_vehicle`; ``yaw`` turns about the vertical and leaves the road as it is).

    Raises:
        ValueError: a height that is not positive or an angle beyond +-pi/4 (:class:`CameraPose`).
    """
    return CameraPose(height=extrinsic["z"], pitch=extrinsic["pitch"], roll=extrinsic["roll"])


def read_camera(path: str | os.PathLike) -> tuple[dict[str, float], dict[str, float]]:
    """``(intrinsic, extrinsic)`` dicts of a ``*_camera.json`` file, all values finite floats: ``intrinsic``
    ``fx fy u0 v0`` (pixels of the full frame), ``extrinsic`` ``baseline pitch roll x y yaw z`` (metres and
    radians, the camera in the vehicle frame: :func:`camera_to_vehicle`; ``z`` is its height above the
    ground, :func:`camera_pose`)."""
    path = Path(path)
    if not path.is_file():
        raise missing(path, "camera file")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise DataFormatError(f"{path}: invalid JSON ({exc})") from exc
    fields = {
        "intrinsic": ("fx", "fy", "u0", "v0"),
        "extrinsic": ("baseline", "pitch", "roll", "x", "y", "yaw", "z"),
    }
    out = []
    for section, keys in fields.items():
        block = data.get(section) if isinstance(data, dict) else None
        if not isinstance(block, dict):
            raise DataFormatError(f"{path}: missing object {section!r}")
        values = {}
        for key in keys:
            value = block.get(key)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise DataFormatError(f"{path}: {section}.{key} must be a finite number, got {value!r}")
            values[key] = float(value)
        out.append(values)
    if out[0]["fx"] <= 0 or out[0]["fy"] <= 0:
        raise DataFormatError(f"{path}: intrinsic focal lengths must be positive")
    return out[0], out[1]


def read_frames(
    root: str | os.PathLike, split: str = "train", cities: Sequence[str] | None = None,
    skip: SkipLog | None = None,
) -> list[FrameRecord]:
    """Index one split into frame records, sorted by city, sequence, frame.

    ``world`` is the city, ``variation`` the split, ``sequence``/``frame`` the two
    numbers of the file name. ``extrinsics`` is the vehicle->camera transform
    (inverse of :func:`camera_to_vehicle`): Cityscapes has no world frame, so the
    vehicle frame (ISO 8855) stands in. Camera files are required.

    ``skip``: None raises on the first bad frame (image header, size, camera file); a :class:`SkipLog`
    records it and leaves the frame out instead.
    """
    root = Path(root)
    image_root = root / "leftImg8bit" / split
    if not image_root.is_dir():
        raise missing(image_root, f"Cityscapes leftImg8bit/{split} folder")
    if cities is None:
        cities = sorted(p.name for p in image_root.iterdir() if p.is_dir())
    records: list[FrameRecord] = []
    for city in cities:
        city_dir = image_root / city
        if not city_dir.is_dir():
            raise missing(city_dir, "city folder")
        names = sorted((m for p in city_dir.iterdir() if (m := _NAME.match(p.name))), key=lambda m: m.string)
        found: list[FrameRecord] = []
        for match in names:
            try:
                found.append(_record(root, split, city, match))
            except DataFormatError as exc:
                if skip is None:
                    raise
                skip.skip(exc, "frame", f"cityscapes/{city}/{split}/{int(match['seq']):06d}/{int(match['frame']):06d}")
        records.extend(_agreeing(found, f"city {split}/{city}", skip))
    return records


def _agreeing(records: list[FrameRecord], what: str, skip: SkipLog | None) -> list[FrameRecord]:
    """The records whose image size most of ``records`` share; each other one raises (or is skipped)."""
    if not records:
        return records
    counts = Counter(r.intrinsics.size for r in records)
    top = max(counts.values())
    size = next(r.intrinsics.size for r in records if counts[r.intrinsics.size] == top)
    kept = []
    for record in records:
        if record.intrinsics.size == size:
            kept.append(record)
            continue
        height, width = record.intrinsics.size
        error = DataFormatError(f"{record.rgb_path}: image is {width}x{height}, but {top} of the {len(records)} "
                                f"frames of {what} are {size[1]}x{size[0]}: this frame is the odd one")
        if skip is None:
            raise error
        skip.skip(error, "frame", record.key)
    return kept


def _record(root: Path, split: str, city: str, match: re.Match) -> FrameRecord:
    stem = f"{match['city']}_{match['seq']}_{match['frame']}"
    rgb_path = root / "leftImg8bit" / split / city / match.string
    gt = root / "gtFine" / split / city
    disparity = root / "disparity" / split / city / f"{stem}_disparity.png"
    camera_path = root / "camera" / split / city / f"{stem}_camera.json"
    intrinsic, extrinsic = read_camera(camera_path)
    width, height = image_size(rgb_path)
    semantic = gt / f"{stem}_gtFine_labelIds.png"
    instance = gt / f"{stem}_gtFine_instanceIds.png"
    to_camera = np.linalg.inv(camera_to_vehicle(extrinsic))
    return FrameRecord(
        dataset="cityscapes",
        world=city,
        variation=split,
        frame=int(match["frame"]),
        sequence=int(match["seq"]),
        intrinsics=Intrinsics(
            intrinsic["fx"], intrinsic["fy"], intrinsic["u0"], intrinsic["v0"], width, height
        ),
        rgb_path=rgb_path,
        semantic_path=semantic if semantic.is_file() else None,
        instance_path=instance if instance.is_file() else None,
        depth_path=disparity if disparity.is_file() else None,
        extrinsics=tuple(float(v) for v in to_camera.reshape(-1)),
        aux=(("camera", camera_path),),
    )


def _require(record: FrameRecord, path: Path | None, what: str) -> Path:
    if path is None:
        raise DataFormatError(f"{record.key}: no {what} on disk for this frame")
    return path


def _label_ids(values: np.ndarray, path: Path) -> np.ndarray:
    bad = values >= _NUM_LABEL_IDS
    if bad.any():
        ids, counts = np.unique(values[bad], return_counts=True)
        pairs = zip(ids[:5].tolist(), counts[:5].tolist(), strict=True)
        listed = ", ".join(f"{i} x {n} px" for i, n in pairs)
        raise DataFormatError(f"{path}: label ids outside 0..{_NUM_LABEL_IDS - 1}: {listed}")
    return values


def load_rgb(record: FrameRecord) -> np.ndarray:
    """``(H, W, 3)`` uint8."""
    return check_size(read_rgb(record.rgb_path), record, record.rgb_path)


def load_semantic(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 train ids 0..18, 255 ignore."""
    path = _require(record, record.semantic_path, "gtFine labelIds")
    labels = _label_ids(check_size(read_index_png(path), record, path), path)
    return LABEL_TO_TRAIN[labels]


def load_instances(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 ``train_id * 1000 + k`` for individual instances, 0 elsewhere."""
    path = _require(record, record.instance_path, "gtFine instanceIds")
    values = check_size(read_index_png(path), record, path)
    is_instance = values >= INSTANCE_DIVISOR
    label = np.where(is_instance, values // INSTANCE_DIVISOR, values)
    train = LABEL_TO_TRAIN[_label_ids(label, path)]
    keep = is_instance & (train != IGNORE_INDEX)
    return np.where(keep, train * INSTANCE_DIVISOR + values % INSTANCE_DIVISOR, 0)


def load_depth(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` float32 metres from disparity (0 where the disparity is invalid)."""
    path = _require(record, record.depth_path, "disparity")
    raw = check_size(read_uint16_png(path), record, path).astype(np.float32)
    _, extrinsic = read_camera(record.aux_path("camera"))
    disparity = (raw - 1.0) / 256.0
    valid = raw > 1.0  # p == 1 would be zero disparity, i.e. infinitely far
    depth = np.zeros_like(raw)
    depth[valid] = extrinsic["baseline"] * record.intrinsics.fx / disparity[valid]
    return depth
