"""Virtual KITTI 2.0.3 reader.

On-disk layout under ``root`` (the official tarballs extracted into one tree)::

    <Scene>/<variation>/frames/rgb/Camera_<c>/rgb_%05d.jpg
    <Scene>/<variation>/frames/classSegmentation/Camera_<c>/classgt_%05d.png      8-bit RGB colours
    <Scene>/<variation>/frames/instanceSegmentation/Camera_<c>/instancegt_%05d.png
    <Scene>/<variation>/frames/depth/Camera_<c>/depth_%05d.png                    16-bit, centimetres
    <Scene>/<variation>/colors.txt       Category r g b (VKITTI classes + Undefined)
    <Scene>/<variation>/bbox.txt         frame cameraID trackID left right top bottom ... (NOTE l r t b)
    <Scene>/<variation>/pose.txt         ... width height length ... camera_space_X/Y/Z ...
    <Scene>/<variation>/info.txt         trackID label model color
    <Scene>/<variation>/intrinsic.txt    frame cameraID K[0,0] K[1,1] K[0,2] K[1,2]
    <Scene>/<variation>/extrinsic.txt    frame cameraID + world->camera 4x4 row-major

The archives spell the segmentation folders ``classSegmentation`` / ``instanceSegmentation``
while the dataset README writes ``classsegmentation`` / ``instancesegmentation``; both are
accepted (the archive spelling first).

``Camera_0`` is the left camera (default), ``Camera_1`` the right one.

Semantic maps index :data:`~sdn3d.data.vkitti1.VKITTI_CLASSES` (matched by name
through ``colors.txt``, whose colours differ slightly from VKITTI 1, e.g. GuardRail);
``Undefined`` pixels get :data:`~sdn3d.data.records.IGNORE_INDEX`.

Instance PNGs hold ``trackID + 1`` per pixel (0 = no instance). The README says 8-bit
indexed (palette) PNG, whose indices are the values; 8-bit grey and 16-bit grey are
accepted too. Instance maps are ``class_id * 1000 + (trackID + 1)``, the same
``k = tid + 1`` as :mod:`sdn3d.data.vkitti1`, with the class from ``info.txt``.

Objects are the rows of ``bbox.txt`` for the chosen camera joined with ``pose.txt``
(3D) and ``info.txt`` (label, model, colour); a bbox row without a pose row is an
error. ``bbox.txt``'s ``occupancy_ratio`` is ``number_pixels / ((right - left) *
(bottom - top))``, the share of the 2D box covered by visible pixels (it reproduces
the published sample rows), the same quantity as Virtual KITTI 1.3.1's motgt ``occupr`` (whose box
area is the inclusive pixel count); it is passed through unchanged as ``occupr``
(:class:`~sdn3d.data.records.ObjectAnnotation`), so even an unoccluded car reads about 0.8. Virtual KITTI 2
has no ``occluded`` flag: the paper's object filter estimates occlusion from ``occupr`` alone
(:func:`~sdn3d.data.vkitti1.paper_object_filter`).
Locations are taken as KITTI's bottom-face centre in the camera frame, as in VKITTI 1;
the VKITTI 2 documentation we could check does not say which point of the box
``camera_space_X/Y/Z`` is.

A sequence's image size is the one its RGB frames agree on, and dimensions must be positive, as in
:mod:`sdn3d.data.vkitti1`; so is the skip policy (:func:`read_frames` ``skip=``): a bad frame (image,
intrinsic or extrinsic row) is recorded and still returned, a bad bbox/pose row loses its object.
"""

from __future__ import annotations

import functools
import os
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from sdn3d.data.errors import DataFormatError, SkipLog, missing
from sdn3d.data.imageio import (
    ColorEncoding,
    build_encoding,
    frames_agreed_size,
    read_index_png,
    read_rgb,
    read_table,
    read_uint16_png,
)
from sdn3d.data.records import FrameRecord, ObjectAnnotation, check_dims, check_size
from sdn3d.data.vkitti1 import (
    MATRIX_COLUMNS,
    VKITTI_SIZE,
    VKITTI_VARIATIONS,
    RowErrorHandler,
    gc_paused,
    intrinsics_for_size,
    row_frame,
)
from sdn3d.labels import IGNORE_INDEX, INSTANCE_DIVISOR, VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import Intrinsics

__all__ = [
    "VKITTI2_SCENES",
    "VKITTI_VARIATIONS",
    "COLORS_HEADER",
    "BBOX_HEADER",
    "POSE_HEADER",
    "INFO_HEADER",
    "INTRINSIC_HEADER",
    "EXTRINSIC_HEADER",
    "scene_to_world",
    "parse_colors",
    "parse_info",
    "read_frames",
    "load_rgb",
    "load_semantic",
    "load_instances",
    "load_depth",
]

VKITTI2_SCENES = ("Scene01", "Scene02", "Scene06", "Scene18", "Scene20")

COLORS_HEADER = ("Category", "r", "g", "b")
BBOX_HEADER = tuple(
    "frame cameraID trackID left right top bottom number_pixels truncation_ratio occupancy_ratio "
    "isMoving".split()
)
POSE_HEADER = tuple(
    "frame cameraID trackID alpha width height length world_space_X world_space_Y world_space_Z "
    "rotation_world_space_y rotation_world_space_x rotation_world_space_z camera_space_X camera_space_Y "
    "camera_space_Z rotation_camera_space_y rotation_camera_space_x rotation_camera_space_z".split()
)
INFO_HEADER = ("trackID", "label", "model", "color")
INTRINSIC_HEADER = ("frame", "cameraID", "K[0,0]", "K[1,1]", "K[0,2]", "K[1,2]")
EXTRINSIC_HEADER = ("frame", "cameraID", *MATRIX_COLUMNS, "0", "0", "0", "1")

_RGB_NAME = re.compile(r"^rgb_(\d{5})\.jpg$")


def scene_to_world(scene: str) -> str:
    """``'Scene06'`` -> ``'0006'``: the Virtual KITTI 1 world (edit benchmark) name."""
    match = re.fullmatch(r"Scene(\d\d)", scene)
    if match is None:
        raise ValueError(f"scene_to_world: expected a name like 'Scene06', got {scene!r}")
    return f"{int(match.group(1)):04d}"


def _cached(path: Path, what: str, parse):
    if not path.is_file():
        raise missing(path, what)
    stat = path.stat()
    return parse(path, stat.st_mtime_ns, stat.st_size)


def parse_colors(path: str | os.PathLike) -> ColorEncoding:
    """``colors.txt`` as a colour table onto VKITTI_CLASSES (Undefined -> 255)."""
    return _cached(Path(path), "colors.txt", _parse_colors)


@functools.lru_cache(maxsize=64)
def _parse_colors(path: Path, _mtime: int, _size: int) -> ColorEncoding:
    entries = []
    for row in read_table(path, COLORS_HEADER, "colors.txt"):
        name = row.text("Category")
        if name == "Undefined":
            class_id = IGNORE_INDEX
        elif name in VKITTI_CLASS_INDEX:
            class_id = VKITTI_CLASS_INDEX[name]
        else:
            raise DataFormatError(f"{path}:{row.lineno}: unknown category {name!r}")
        rgb = tuple(row.integer(c) for c in "rgb")
        entries.append((row.lineno, rgb, class_id, -1))
    if not entries:
        raise DataFormatError(f"{path}: colors.txt lists no colours")
    return build_encoding(path, entries)


def parse_info(path: str | os.PathLike) -> dict[int, tuple[str, str, str]]:
    """``info.txt``: trackID -> (label, model, color)."""
    return _cached(Path(path), "info.txt", _parse_info)


@functools.lru_cache(maxsize=64)
def _parse_info(path: Path, _mtime: int, _size: int) -> dict[int, tuple[str, str, str]]:
    info: dict[int, tuple[str, str, str]] = {}
    for row in read_table(path, INFO_HEADER, "info.txt"):
        tid = row.integer("trackID")
        if tid in info or not 0 <= tid < INSTANCE_DIVISOR - 1:
            raise DataFormatError(f"{path}:{row.lineno}: trackID {tid} repeated or outside [0, 998]")
        info[tid] = (row.text("label"), row.text("model"), row.text("color"))
    return info


def _table(path: Path, header: Sequence[str], what: str, on_error: RowErrorHandler | None):
    return read_table(path, header, what,
                      None if on_error is None else (lambda exc, tokens: on_error(exc, row_frame(tokens))))


def _keyed(rows, path: Path, what: str, on_error: RowErrorHandler | None = None) -> dict[tuple[int, int, int], object]:
    table = {}
    for row in rows:
        frame = None
        try:
            frame = row.integer("frame")
            key = (frame, row.integer("cameraID"), row.integer("trackID"))
            if key in table:
                raise DataFormatError(f"{path}:{row.lineno}: {what} repeats frame/camera/track {key}")
        except DataFormatError as exc:
            if on_error is None:
                raise
            on_error(exc, frame)
            continue
        table[key] = row
    return table


def _objects(seq: Path, camera: int,
             on_error: RowErrorHandler | None = None) -> dict[int, tuple[ObjectAnnotation, ...]]:
    bbox_path, pose_path = seq / "bbox.txt", seq / "pose.txt"
    poses = _keyed(_table(pose_path, POSE_HEADER, "pose.txt", on_error), pose_path, "pose.txt", on_error)
    info = parse_info(seq / "info.txt")
    objects: dict[int, list[ObjectAnnotation]] = {}
    for box in _table(bbox_path, BBOX_HEADER, "bbox.txt", on_error):
        frame = None
        try:
            frame, cam, tid = box.integer("frame"), box.integer("cameraID"), box.integer("trackID")
            if cam != camera:
                continue
            pose = poses.get((frame, cam, tid))
            if pose is None:
                raise DataFormatError(
                    f"{bbox_path}:{box.lineno}: no row in {pose_path} for frame {frame} camera {cam} track {tid}"
                )
            if tid not in info:
                raise DataFormatError(
                    f"{bbox_path}:{box.lineno}: track {tid} is not listed in {seq / 'info.txt'}"
                )
            label, model, color = info[tid]
            annotation = ObjectAnnotation(
                track_id=tid,
                label=label,
                box2d=tuple(box.number(c) for c in ("left", "top", "right", "bottom")),
                dims=(pose.number("length"), pose.number("height"), pose.number("width")),
                location=tuple(pose.number(f"camera_space_{c}") for c in "XYZ"),
                ry=pose.number("rotation_camera_space_y"),
                alpha=pose.number("alpha"),
                truncr=box.number("truncation_ratio"),
                occupr=box.number("occupancy_ratio"),
                rx=pose.number("rotation_camera_space_x"),
                rz=pose.number("rotation_camera_space_z"),
                moving=box.flag("isMoving"),
                model=model,
                color=color,
                num_pixels=box.integer("number_pixels"),
            )
            check_dims(annotation.dims, label, f"{pose_path}:{pose.lineno}")
        except DataFormatError as exc:
            if on_error is None:
                raise
            on_error(exc, frame)
            continue
        objects.setdefault(frame, []).append(annotation)
    return {frame: tuple(objs) for frame, objs in objects.items()}


def _per_frame(path: Path, header: Sequence[str], what: str, camera: int,
               on_error: RowErrorHandler | None = None) -> dict[int, tuple[float, ...]]:
    """Columns 2.. of a ``frame cameraID ...`` file for one camera, keyed by frame."""
    values: dict[int, tuple[float, ...]] = {}
    for row in _table(path, header, what, on_error):
        frame = None
        try:
            if row.integer("cameraID") != camera:
                continue
            frame = row.integer("frame")
            if frame in values:
                raise DataFormatError(f"{path}:{row.lineno}: frame {frame} camera {camera} listed twice")
            numbers = tuple(row.number(i) for i in range(2, len(header)))
            if len(header) == len(EXTRINSIC_HEADER) and numbers[12:] != (0.0, 0.0, 0.0, 1.0):
                raise DataFormatError(f"{path}:{row.lineno}: last matrix row must be 0 0 0 1")
        except DataFormatError as exc:
            if on_error is None:
                raise
            on_error(exc, frame)
            continue
        values[frame] = numbers
    return values


def _camera_index(camera: int | str) -> int:
    if isinstance(camera, str):
        match = re.fullmatch(r"(?:Camera_)?([01])", camera)
        camera = int(match.group(1)) if match else -1
    if camera not in (0, 1):
        raise ValueError(f"camera must be 0, 1, 'Camera_0' or 'Camera_1', got {camera!r}")
    return camera


def read_frames(
    root: str | os.PathLike,
    scenes: Sequence[str] | None = None,
    variations: Sequence[str] | None = None,
    camera: int | str = 0,
    annotations: bool = True,
    skip: SkipLog | None = None,
) -> list[FrameRecord]:
    """Index a Virtual KITTI 2.0.3 tree into frame records (sorted by scene, variation, frame).

    Args:
        root: folder holding the ``Scene*`` folders.
        scenes, variations: subsets to read; None reads every folder present.
        camera: 0/``'Camera_0'`` (left, default) or 1/``'Camera_1'``.
        annotations: parse bbox/pose/info/intrinsic/extrinsic (they must then exist);
            without them intrinsics are the nominal VKITTI ones and objects are empty.
        skip: None raises on the first bad frame or row; a :class:`SkipLog` records them instead (module doc).
    """
    root = Path(root)
    cam = _camera_index(camera)
    if not root.is_dir():
        raise missing(root, "Virtual KITTI 2 root folder")
    if scenes is None:
        scenes = sorted(p.name for p in root.iterdir() if p.is_dir() and p.name.startswith("Scene"))
    records: list[FrameRecord] = []
    for scene in scenes:
        if not (root / scene).is_dir():
            raise missing(root / scene, "scene folder")
        names = variations
        if names is None:
            names = sorted(p.name for p in (root / scene).iterdir() if (p / "frames").is_dir())
        with gc_paused():  # as in vkitti1.read_frames: no cycles among the records, and many of them
            for variation in names:
                records.extend(_read_sequence(root / scene / variation, scene, variation, cam, annotations, skip))
    return records


def _modality_dir(seq: Path, modality: str, camera: str) -> Path:
    """``frames/<modality>/<camera>``, or its all-lowercase spelling (the README's) if only that exists."""
    for folder in dict.fromkeys((modality, modality.lower())):
        path = seq / "frames" / folder / camera
        if path.is_dir():
            return path
    return seq / "frames" / modality / camera


def _read_sequence(seq: Path, scene: str, variation: str, cam: int, annotations: bool,
                   skip: SkipLog | None = None) -> list[FrameRecord]:
    camera = f"Camera_{cam}"
    rgb_dir = seq / "frames" / "rgb" / camera
    if not rgb_dir.is_dir():
        raise missing(rgb_dir, "rgb folder")
    frames = sorted(int(m.group(1)) for p in rgb_dir.iterdir() if (m := _RGB_NAME.match(p.name)))
    if not frames:
        return []
    dirs = {m: _modality_dir(seq, m, camera) for m in ("classSegmentation", "instanceSegmentation", "depth")}
    if dirs["classSegmentation"].is_dir() and not (seq / "colors.txt").is_file():
        raise missing(seq / "colors.txt", "colors.txt")

    def key(frame: int | None) -> str | None:  # FrameRecord.key
        return None if frame is None else f"vkitti2/{scene}/{variation}/{camera}/{frame:05d}"

    bad: dict[int, DataFormatError] = {}  # frames to drop (skip policy only)

    def bad_frame(exc: DataFormatError, frame: int | None) -> None:
        if frame is None or frame not in frames:
            skip.skip(exc, "frame", key(frame))
        else:
            bad.setdefault(frame, exc)

    intrinsics: dict[int, tuple[float, ...]] = {}
    extrinsics: dict[int, tuple[float, ...]] = {}
    objects: dict[int, tuple[ObjectAnnotation, ...]] = {}
    if annotations:
        on_frame = None if skip is None else bad_frame
        intrinsics = _per_frame(seq / "intrinsic.txt", INTRINSIC_HEADER, "intrinsic.txt", cam, on_frame)
        extrinsics = _per_frame(seq / "extrinsic.txt", EXTRINSIC_HEADER, "extrinsic.txt", cam, on_frame)
        for name, table in (("intrinsic.txt", intrinsics), ("extrinsic.txt", extrinsics)):
            absent = [f for f in frames if f not in table]
            if absent and skip is None:
                raise DataFormatError(f"{seq / name}: no {camera} entry for frame(s) {absent[:10]}")
            for frame in absent:
                bad.setdefault(frame, DataFormatError(f"{seq / name}: no {camera} entry for frame {frame}"))
        objects = _objects(seq, cam, None if skip is None else (lambda exc, frame: skip.skip(exc, "object",
                                                                                             key(frame))))
    size = frames_agreed_size({f: rgb_dir / f"rgb_{f:05d}.jpg" for f in frames},
                              f"sequence {scene}/{variation}/{camera}", bad, skip is None, VKITTI_SIZE)
    nominal = intrinsics_for_size(size)
    for frame in sorted(bad):
        skip.skip(bad[frame], "frame", key(frame))
    made: dict[tuple[float, ...], Intrinsics] = {}

    def frame_intrinsics(frame: int) -> Intrinsics:
        if not annotations or frame not in intrinsics:  # no intrinsic row: a skipped frame
            return nominal
        k = intrinsics[frame]
        if k not in made:
            made[k] = Intrinsics(k[0], k[1], k[2], k[3], nominal.width, nominal.height)
        return made[k]

    def path(modality: str, prefix: str, frame: int) -> Path | None:
        return dirs[modality] / f"{prefix}_{frame:05d}.png" if dirs[modality].is_dir() else None

    aux_files = (("colors", "colors.txt"), ("info", "info.txt"))
    aux = tuple((n, seq / f) for n, f in aux_files if (seq / f).is_file())
    return [
        FrameRecord(
            dataset="vkitti2",
            world=scene,
            variation=variation,
            frame=frame,
            intrinsics=frame_intrinsics(frame),
            rgb_path=rgb_dir / f"rgb_{frame:05d}.jpg",
            semantic_path=path("classSegmentation", "classgt", frame),
            instance_path=path("instanceSegmentation", "instancegt", frame),
            depth_path=path("depth", "depth", frame),
            extrinsics=extrinsics.get(frame) if annotations else None,
            objects=objects.get(frame, ()),
            camera=camera,
            aux=aux,
        )
        for frame in frames
    ]


def _require(record: FrameRecord, path: Path | None, what: str) -> Path:
    if path is None:
        raise DataFormatError(f"{record.key}: no {what} on disk for this frame")
    return path


def _aux(record: FrameRecord, name: str) -> Path:
    try:
        return record.aux_path(name)
    except KeyError:
        raise missing(record.rgb_path.parents[3] / f"{name}.txt", f"{name}.txt") from None


def load_rgb(record: FrameRecord) -> np.ndarray:
    """``(H, W, 3)`` uint8 (decoded JPEG)."""
    return check_size(read_rgb(record.rgb_path), record, record.rgb_path)


def load_semantic(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 indices into VKITTI_CLASSES, 255 for Undefined."""
    path = _require(record, record.semantic_path, "class segmentation")
    rgb = check_size(read_rgb(path), record, path)
    encoding = parse_colors(_aux(record, "colors"))
    return encoding.class_ids[encoding.lookup(rgb, path)]


def load_instances(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 ``class_id * 1000 + trackID + 1``, 0 for no instance."""
    path = _require(record, record.instance_path, "instance segmentation")
    values = check_size(read_index_png(path), record, path)
    info_path = _aux(record, "info")
    info = parse_info(info_path)
    lut = np.full(max(info, default=0) + 2, -1, dtype=np.int64)
    lut[0] = 0
    for tid, (label, _, _) in info.items():
        if label not in VKITTI_CLASS_INDEX:
            raise DataFormatError(f"{info_path}: track {tid} has unknown label {label!r}")
        lut[tid + 1] = VKITTI_CLASS_INDEX[label] * INSTANCE_DIVISOR + tid + 1
    unknown = values >= len(lut)
    unknown[~unknown] = lut[values[~unknown]] < 0
    if unknown.any():
        bad, counts = np.unique(values[unknown], return_counts=True)
        listed = ", ".join(f"{v} (track {v - 1}) x {n} px" for v, n in zip(bad[:5], counts[:5], strict=True))
        raise DataFormatError(f"{path}: instance values with no track in {info_path}: {listed}")
    return lut[values]


def load_depth(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` float32 metres (centimetres / 100; far plane 655.35 m)."""
    path = _require(record, record.depth_path, "depth")
    return check_size(read_uint16_png(path), record, path).astype(np.float32) / np.float32(100.0)
