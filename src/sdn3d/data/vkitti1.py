"""Virtual KITTI 1.3.1 reader.

On-disk layout under ``root`` (the official tarballs extracted side by side)::

    vkitti_1.3.1_rgb/<world>/<variation>/%05d.png              8-bit RGB, 1242x375
    vkitti_1.3.1_scenegt/<world>/<variation>/%05d.png          8-bit RGB colour-coded classes/instances
    vkitti_1.3.1_scenegt/<world>_<variation>_scenegt_rgb_encoding.txt
    vkitti_1.3.1_depthgt/<world>/<variation>/%05d.png          16-bit grey, centimetres
    vkitti_1.3.1_motgt/<world>_<variation>.txt                 objects (KITTI-like, see MOTGT_HEADER)
    vkitti_1.3.1_extrinsicsgt/<world>_<variation>.txt          world->camera 4x4 per frame

Scene ground truth: the encoding file maps colours to ``Category`` (stuff classes,
one colour each) or ``Category:tid`` (one colour per Car/Van track, ``tid`` as in
motgt). Semantic maps index :data:`VKITTI_CLASSES` (14 classes, no ignore label);
instance maps are ``class_id * 1000 + (tid + 1)`` so that track 0 is not confused
with "no instance": ``tid = id % 1000 - 1``.

motgt ``occupr`` is the share of the object's 2D box that its visible pixels cover (an unoccluded car reads
about 0.8), not the visible share of the object; ``occluded`` (0 / 1 / 2: fully visible / partly / largely
occluded) is the only other occlusion signal of the format. :func:`paper_object_filter` uses both.

Depth is the z-buffer depth (distance to the camera plane), stored in centimetres;
the far plane (sky) is 65535 cm = 655.35 m and is returned as such.

A sequence's image size is the one its RGB frames agree on (:func:`~sdn3d.data.imageio.agreed_size`,
ties going to the format's 1242x375): an unreadable or odd-sized frame, the first one included, is named
as the bad file. Object dimensions must be positive (:func:`~sdn3d.data.records.check_dims`).

Skip policy: :func:`read_frames` given a :class:`~sdn3d.data.errors.SkipLog` does not raise for a bad
frame (unreadable or odd-sized image, no extrinsics) or a bad motgt row: it records it there; the frame is
still returned (so splits do not shift) and :func:`~sdn3d.data.sources.load_split` drops it, a bad row's
object is left out. Missing folders and files, and bad headers, raise under every policy.
"""

from __future__ import annotations

import contextlib
import functools
import gc
import math
import os
import re
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import numpy as np

from sdn3d.data.errors import DataFormatError, SkipLog, missing
from sdn3d.data.imageio import (
    ColorEncoding,
    TableRow,
    build_encoding,
    frames_agreed_size,
    read_rgb,
    read_table,
    read_uint16_png,
)
from sdn3d.data.records import FrameRecord, ObjectAnnotation, check_dims, check_size
from sdn3d.labels import INSTANCE_DIVISOR, VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS, Intrinsics

__all__ = [
    "VKITTI1_WORLDS",
    "VKITTI_VARIATIONS",
    "MOTGT_HEADER",
    "EXTRINSICS_HEADER",
    "PUBLISHED_EXTRINSICS_HEADER",
    "ENCODING_HEADER",
    "MATRIX_COLUMNS",
    "parse_encoding",
    "parse_motgt",
    "parse_extrinsics",
    "read_frames",
    "VKITTI_SIZE",
    "intrinsics_for_size",
    "RowErrorHandler",
    "row_frame",
    "load_rgb",
    "load_semantic",
    "load_instances",
    "load_depth",
    "paper_object_filter",
    "occlusion_estimate",
    "UNOCCLUDED_OCCUPR",
    "gc_paused",
]

VKITTI1_WORLDS = ("0001", "0002", "0006", "0018", "0020")
VKITTI_VARIATIONS = (
    "clone", "morning", "sunset", "overcast", "fog", "rain",
    "15-deg-left", "15-deg-right", "30-deg-left", "30-deg-right",
)  # fmt: skip

MOTGT_HEADER = tuple(
    "frame tid label truncated occluded alpha l t r b w3d h3d l3d x3d y3d z3d ry rx rz "
    "truncr occupr orig_label moving model color".split()
)
#: The 12 varying matrix columns ``r1,1 r1,2 r1,3 t1 ... r3,3 t3``. The header's last four words name the
#: constant last matrix row; published files word them differently (``0 0 0 1``, ``0 0.1 0.2 1``, ...), so
#: only the first 13 words are checked, and every data row's last four numbers must read 0 0 0 1.
MATRIX_COLUMNS = tuple(c for i in (1, 2, 3) for c in (f"r{i},1", f"r{i},2", f"r{i},3", f"t{i}"))
EXTRINSICS_HEADER = ("frame", *MATRIX_COLUMNS, "0", "0", "0", "1")
#: The header as the published Virtual KITTI 1.3.1 extrinsicsgt files word it (what the fixtures write).
PUBLISHED_EXTRINSICS_HEADER = ("frame", *MATRIX_COLUMNS, "0", "0.1", "0.2", "1")
ENCODING_HEADER = ("Category(:id)", "r", "g", "b")

_FRAME_PNG = re.compile(r"^(\d{5})\.png$")

#: The size Virtual KITTI (1 and 2) images have, ``(width, height)``; it wins ties in a sequence's size vote.
VKITTI_SIZE = (VKITTI_INTRINSICS.width, VKITTI_INTRINSICS.height)

#: ``on_error(error, frame)`` for a bad annotation row; ``frame`` is the row's frame number when it can be read.
RowErrorHandler = Callable[[DataFormatError, "int | None"], None]


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """Pause Python's cyclic garbage collector (if it runs) for the duration of the block.

    Indexing a dataset allocates hundreds of thousands of small objects that form no cycle (records, rows,
    tuples); each batch of allocations would otherwise start a collection that walks every object made so
    far, which took about half of the time to index the 21,260 frames of Virtual KITTI 1.3.1
    (``benchmarks/index_frames.py``). Reference counting still frees everything as usual.
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def row_frame(tokens: Sequence[str]) -> int | None:
    """The frame number in the first field of a broken row, if it is one."""
    try:
        value = float(tokens[0]) if tokens else math.nan
    except ValueError:
        return None
    return int(value) if math.isfinite(value) and value == int(value) else None


def parse_encoding(path: str | os.PathLike) -> ColorEncoding:
    """Parse a ``*_scenegt_rgb_encoding.txt`` file (cached per file version)."""
    path = Path(path)
    if not path.is_file():
        raise missing(path, "scenegt rgb encoding file")
    stat = path.stat()
    return _parse_encoding_cached(path, stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=64)
def _parse_encoding_cached(path: Path, _mtime_ns: int, _size: int) -> ColorEncoding:
    entries = []
    for row in read_table(path, ENCODING_HEADER, "scenegt rgb encoding file"):
        category = row.text("Category(:id)")
        name, _, tid_text = category.partition(":")
        if name not in VKITTI_CLASS_INDEX:
            raise DataFormatError(
                f"{path}:{row.lineno}: unknown category {name!r} (expected one of {list(VKITTI_CLASS_INDEX)})"
            )
        tid = -1
        if tid_text:
            if not tid_text.isdigit() or int(tid_text) >= INSTANCE_DIVISOR - 1:
                raise DataFormatError(
                    f"{path}:{row.lineno}: track id in {category!r} must be an integer in [0, 998]"
                )
            tid = int(tid_text)
        rgb = tuple(row.integer(c) for c in "rgb")
        if not all(0 <= v <= 255 for v in rgb):
            raise DataFormatError(f"{path}:{row.lineno}: colour {rgb} outside [0, 255]")
        entries.append((row.lineno, rgb, VKITTI_CLASS_INDEX[name], tid))
    if not entries:
        raise DataFormatError(f"{path}: encoding file lists no colours")
    return build_encoding(path, entries)


#: Column positions in a motgt row.
_MOTGT = {name: i for i, name in enumerate(MOTGT_HEADER)}
_MOTGT_NUMBERS = tuple(_MOTGT[c] for c in ("l", "t", "r", "b", "l3d", "h3d", "w3d", "x3d", "y3d", "z3d", "ry",
                                           "alpha", "truncr", "occupr", "rx", "rz"))
_MOTGT_INTEGERS = tuple(_MOTGT[c] for c in ("frame", "tid", "truncated", "occluded"))


def _motgt_annotation(row: TableRow) -> ObjectAnnotation:
    """The row's object, its values checked one by one (errors name the file, line and column)."""
    return ObjectAnnotation(
        track_id=row.integer("tid"),
        label=row.text("label"),
        box2d=tuple(row.number(c) for c in "ltrb"),
        dims=(row.number("l3d"), row.number("h3d"), row.number("w3d")),
        location=(row.number("x3d"), row.number("y3d"), row.number("z3d")),
        ry=row.number("ry"),
        alpha=row.number("alpha"),
        truncr=row.number("truncr"),
        occupr=row.number("occupr"),
        truncated=row.integer("truncated"),
        occluded=row.integer("occluded"),
        rx=row.number("rx"),
        rz=row.number("rz"),
        orig_label=row.text("orig_label"),
        moving=row.flag("moving"),
        model=row.text("model"),
        color=row.text("color"),
    )


def _motgt_values(rows: Sequence[TableRow]) -> tuple[list[list[float]], list[list[int]], list[bool]] | None:
    """Numbers ``(N, 16)`` (:data:`_MOTGT_NUMBERS` order), integers ``(N, 4)`` (frame, tid, truncated, occluded)
    and moving flags of every row, converted in one numpy pass; None when some value is not what the format
    expects (not a finite number, not an integer, not a 0/1/True/False flag): the rows are then read one by
    one by :func:`_motgt_annotation`, whose error names the line and column. Same values as that path."""
    tokens = [row.tokens for row in rows]
    try:  # Python's float() is what TableRow.number uses (and faster than numpy's string conversion)
        numbers = [[float(t[i]) for i in _MOTGT_NUMBERS] for t in tokens]
        integers = np.array([[float(t[i]) for i in _MOTGT_INTEGERS] for t in tokens], dtype=np.float64)
    except ValueError:
        return None
    moving = [t[_MOTGT["moving"]].lower() for t in tokens]
    finite = np.isfinite(np.array(numbers, dtype=np.float64)).all() and np.isfinite(integers).all()
    if not (finite and (integers == np.trunc(integers)).all() and set(moving) <= {"0", "1", "true", "false"}):
        return None
    return numbers, integers.astype(np.int64).tolist(), [m in ("1", "true") for m in moving]


def _motgt_objects(rows: Sequence[TableRow]) -> list[tuple[TableRow, int, ObjectAnnotation]] | None:
    """``(row, frame, object)`` of every row when all are well formed (:func:`_motgt_values`), else None."""
    values = _motgt_values(rows)
    if values is None:
        return None
    name, label, model, color = (_MOTGT[c] for c in ("orig_label", "label", "model", "color"))
    out = []
    for row, n, (frame, tid, truncated, occluded), moving in zip(rows, *values, strict=True):
        tokens = row.tokens
        out.append((row, frame, ObjectAnnotation(
            track_id=tid, label=tokens[label], box2d=(n[0], n[1], n[2], n[3]), dims=(n[4], n[5], n[6]),
            location=(n[7], n[8], n[9]), ry=n[10], alpha=n[11], truncr=n[12], occupr=n[13], truncated=truncated,
            occluded=occluded, rx=n[14], rz=n[15], orig_label=tokens[name], moving=moving, model=tokens[model],
            color=tokens[color])))
    return out


def parse_motgt(path: str | os.PathLike, on_error: RowErrorHandler | None = None
                ) -> dict[int, tuple[ObjectAnnotation, ...]]:
    """Objects per frame from a motgt file (``w3d h3d l3d`` are reordered to ``dims=(l, h, w)``).

    A bad row (field count, a value, a repeated frame/track, non-positive dimensions) raises naming the file
    and line; with ``on_error`` it is left out and ``on_error(error, frame)`` is called instead. Well-formed
    files are converted in one numpy pass (:func:`_motgt_objects`; a full Virtual KITTI 1.3.1 release has
    some 200,000 rows); a file with any malformed value is read row by row through the checked getters, so
    its errors are the same.
    """
    objects: dict[int, list[ObjectAnnotation]] = {}
    seen: dict[tuple[int, int], int] = {}
    rows = read_table(path, MOTGT_HEADER, "motgt file",
                      None if on_error is None else (lambda exc, tokens: on_error(exc, row_frame(tokens))))
    fast = _motgt_objects(rows)
    for k, row in enumerate(rows):
        frame: int | None = None
        try:
            if fast is None:
                frame = row.integer("frame")
                annotation = _motgt_annotation(row)
            else:
                _, frame, annotation = fast[k]
            tid = annotation.track_id
            if (frame, tid) in seen:
                raise DataFormatError(
                    f"{row.path}:{row.lineno}: frame {frame} track {tid} already annotated "
                    f"on line {seen[frame, tid]}"
                )
            check_dims(annotation.dims, annotation.label, f"{row.path}:{row.lineno}")
        except DataFormatError as exc:
            if on_error is None:
                raise
            on_error(exc, frame)
            continue
        seen[frame, tid] = row.lineno
        objects.setdefault(frame, []).append(annotation)
    return {frame: tuple(objs) for frame, objs in objects.items()}


def _numbers(tokens: list[str]) -> list[float] | None:
    """Every token as a finite float, or None (the row is then read column by column, for its error)."""
    try:
        values = [float(t) for t in tokens]
    except ValueError:
        return None
    return values if all(map(math.isfinite, values)) else None


def parse_extrinsics(path: str | os.PathLike, on_error: RowErrorHandler | None = None
                     ) -> dict[int, tuple[float, ...]]:
    """World->camera matrices per frame (row-major 16-tuples) from an extrinsicsgt file.

    A bad row raises naming the file and line; with ``on_error`` it is left out (its frame then has no
    matrix) and ``on_error(error, frame)`` is called instead.
    """
    matrices: dict[int, tuple[float, ...]] = {}
    rows = read_table(path, EXTRINSICS_HEADER, "extrinsics file",
                      None if on_error is None else (lambda exc, tokens: on_error(exc, row_frame(tokens))),
                      named_columns=1 + len(MATRIX_COLUMNS))
    for row in rows:
        frame: int | None = None
        try:
            fast = _numbers(row.tokens)
            frame = row.integer("frame") if fast is None or fast[0] != int(fast[0]) else int(fast[0])
            if frame in matrices:
                raise DataFormatError(f"{row.path}:{row.lineno}: frame {frame} listed twice")
            values = fast[1:13] if fast is not None else [row.number(i) for i in range(1, 13)]
            last = fast[13:] if fast is not None else [row.number(i) for i in range(13, 17)]
            if last != [0.0, 0.0, 0.0, 1.0]:
                raise DataFormatError(f"{row.path}:{row.lineno}: last matrix row must be 0 0 0 1, got {last}")
        except DataFormatError as exc:
            if on_error is None:
                raise
            on_error(exc, frame)
            continue
        matrices[frame] = (*values, 0.0, 0.0, 0.0, 1.0)
    return matrices


def _subdirs(folder: Path, requested: Sequence[str] | None, what: str) -> list[str]:
    if requested is None:
        return sorted(p.name for p in folder.iterdir() if p.is_dir())
    for name in requested:
        if not (folder / name).is_dir():
            raise missing(folder / name, what)
    return list(requested)


def intrinsics_for_size(size: tuple[int, int] | None) -> Intrinsics:
    """VKITTI intrinsics at the stored ``(width, height)`` (rescaled if not 1242x375; nominal for None)."""
    if size is None or tuple(size) == VKITTI_SIZE:
        return VKITTI_INTRINSICS
    return VKITTI_INTRINSICS.resized(*size)


def read_frames(
    root: str | os.PathLike,
    worlds: Sequence[str] | None = None,
    variations: Sequence[str] | None = None,
    annotations: bool = True,
    skip: SkipLog | None = None,
) -> list[FrameRecord]:
    """Index a Virtual KITTI 1.3.1 tree into frame records, sorted by world, variation, frame.

    Args:
        root: folder holding ``vkitti_1.3.1_rgb`` and the other modality folders.
        worlds, variations: subsets to read; None reads every folder present.
        annotations: parse motgt and extrinsics (both must then exist).
        skip: None raises on the first bad frame or row; a :class:`SkipLog` records them instead
            (module doc: skipped frames are still returned, ``load_split`` drops them).

    Scene GT and depth paths are set when their sequence folders exist, else None.
    """
    root = Path(root)
    rgb_root = root / "vkitti_1.3.1_rgb"
    if not rgb_root.is_dir():
        raise missing(rgb_root, "Virtual KITTI 1.3.1 rgb folder")
    records: list[FrameRecord] = []
    with gc_paused():
        for world in _subdirs(rgb_root, worlds, "world folder"):
            for variation in _subdirs(rgb_root / world, variations, "variation folder"):
                records.extend(_read_sequence(root, world, variation, annotations, skip))
    return records


def _read_sequence(root: Path, world: str, variation: str, annotations: bool,
                   skip: SkipLog | None = None) -> list[FrameRecord]:
    rgb_dir = root / "vkitti_1.3.1_rgb" / world / variation
    frames = sorted(int(m.group(1)) for p in rgb_dir.iterdir() if (m := _FRAME_PNG.match(p.name)))
    if not frames:
        return []
    scenegt_dir = root / "vkitti_1.3.1_scenegt" / world / variation
    depth_dir = root / "vkitti_1.3.1_depthgt" / world / variation
    encoding = root / "vkitti_1.3.1_scenegt" / f"{world}_{variation}_scenegt_rgb_encoding.txt"
    has_scenegt = scenegt_dir.is_dir()
    if has_scenegt and not encoding.is_file():
        raise missing(encoding, "scenegt rgb encoding file")

    def key(frame: int | None) -> str | None:  # FrameRecord.key
        return None if frame is None else f"vkitti1/{world}/{variation}/{frame:05d}"

    bad: dict[int, DataFormatError] = {}  # frames to drop (skip policy only)

    def bad_frame(exc: DataFormatError, frame: int | None) -> None:
        if frame is None or frame not in frames:
            skip.skip(exc, "frame", key(frame))  # a row of no frame we have: report it, nothing to drop
        else:
            bad.setdefault(frame, exc)

    objects: dict[int, tuple[ObjectAnnotation, ...]] = {}
    extrinsics: dict[int, tuple[float, ...]] = {}
    if annotations:
        objects = parse_motgt(root / "vkitti_1.3.1_motgt" / f"{world}_{variation}.txt",
                              None if skip is None else (lambda exc, frame: skip.skip(exc, "object", key(frame))))
        extrinsics_path = root / "vkitti_1.3.1_extrinsicsgt" / f"{world}_{variation}.txt"
        extrinsics = parse_extrinsics(extrinsics_path, None if skip is None else bad_frame)
        absent = [f for f in frames if f not in extrinsics]
        if absent and skip is None:
            raise DataFormatError(f"{extrinsics_path}: no matrix for frame(s) {absent[:10]}")
        for frame in absent:
            bad.setdefault(frame, DataFormatError(f"{extrinsics_path}: no matrix for frame {frame}"))
    names = {f: f"{f:05d}.png" for f in frames}
    rgb_paths = {f: rgb_dir / names[f] for f in frames}
    size = frames_agreed_size(rgb_paths, f"sequence {world}/{variation}", bad, skip is None, VKITTI_SIZE)
    intrinsics = intrinsics_for_size(size)
    for frame in sorted(bad):
        skip.skip(bad[frame], "frame", key(frame))
    has_depth = depth_dir.is_dir()
    aux = (("encoding", encoding),) if has_scenegt else ()
    records = []
    for frame in frames:
        scenegt = scenegt_dir / names[frame] if has_scenegt else None
        records.append(FrameRecord(
            dataset="vkitti1", world=world, variation=variation, frame=frame, intrinsics=intrinsics,
            rgb_path=rgb_paths[frame], semantic_path=scenegt, instance_path=scenegt,
            depth_path=depth_dir / names[frame] if has_depth else None,
            extrinsics=extrinsics.get(frame), objects=objects.get(frame, ()), aux=aux,
        ))
    return records


def _require(record: FrameRecord, path: Path | None, what: str) -> Path:
    if path is None:
        raise DataFormatError(f"{record.key}: no {what} on disk for this frame")
    return path


def load_rgb(record: FrameRecord) -> np.ndarray:
    """``(H, W, 3)`` uint8."""
    return check_size(read_rgb(record.rgb_path), record, record.rgb_path)


def _scenegt(record: FrameRecord) -> tuple[np.ndarray, np.ndarray]:
    path = _require(record, record.semantic_path, "scene ground truth")
    rgb = check_size(read_rgb(path), record, path)
    return parse_encoding(record.aux_path("encoding")).decode(rgb, path)


def load_semantic(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 indices into :data:`VKITTI_CLASSES`."""
    return _scenegt(record)[0]


def load_instances(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` int64 ``class_id * 1000 + tid + 1`` for Car/Van tracks, 0 elsewhere."""
    return _scenegt(record)[1]


def load_depth(record: FrameRecord) -> np.ndarray:
    """``(H, W)`` float32 metres (centimetres / 100; far plane 655.35 m)."""
    path = _require(record, record.depth_path, "depth")
    return check_size(read_uint16_png(path), record, path).astype(np.float32) / np.float32(100.0)


#: ``occupr`` (visible pixels / 2D box area) of an unoccluded car: its silhouette does not fill its box. Real
#: Virtual KITTI 1.3.1 / 2 unoccluded cars read about 0.75-0.85; the synthetic ones 0.83-0.93 (median 0.88; 310
#: unoccluded cars of 5 worlds x 24 clone frames at 624x192). The occlusion estimate divides by this.
UNOCCLUDED_OCCUPR = 0.8


def occlusion_estimate(obj: ObjectAnnotation) -> float:
    """The share of ``obj`` hidden by other things, as far as an annotation file tells: ``1 - occupr /``
    :data:`UNOCCLUDED_OCCUPR`, clipped to ``[0, 1]``.

    The files do not store the visible share of the object itself, only ``occupr``, the share of the visible
    pixels' 2D box that they cover (Virtual KITTI 1.3.1 motgt ``occupr``, Virtual KITTI 2 ``occupancy_ratio``).
    An unoccluded car covers about :data:`UNOCCLUDED_OCCUPR` of its box, so the ratio to it estimates the
    visible share. It under-estimates occlusion when the occluder cuts a whole side off (the box shrinks with
    the visible pixels), which the ``occluded`` flag catches where the format has one (:func:`paper_object_filter`).
    """
    return min(max(1.0 - obj.occupr / UNOCCLUDED_OCCUPR, 0.0), 1.0)


def paper_object_filter(
    obj: ObjectAnnotation,
    visible_pixels: int,
    min_pixels: int = 256,
    max_occlusion: float = 0.7,
    max_truncation: float = 0.7,
) -> bool:
    """The 3D-SDN object filter: keep objects with more than 256 visible pixels, less than 70% occlusion and
    less than 70% truncation, computed from what every Virtual KITTI file holds, synthetic or real.

    - Occlusion: :func:`occlusion_estimate` ``< max_occlusion`` (from ``occupr``, visible / box area: so
      ``occupr > 0.24`` at the defaults), and, where the format has the KITTI-like ``occluded`` flag (Virtual
      KITTI 1.3.1 and the synthetic data; not Virtual KITTI 2), ``occluded < 2`` (not "largely occluded";
      the generator sets 2 below 40 % of the object's in-frame pixels visible). Neither can be the true
      visible share, which the files do not hold. Measured on synthetic cars whose true share the generator
      knows (423 cars over 256 px and under 70 % truncation, 5 worlds x 24 clone frames): the true rule
      (visible share > 0.3) keeps 411; ``occupr`` alone keeps 422 (11 heavily occluded cars whose visible
      part fills its own box), the flag and ``occupr`` together keep 408 (3 cars 60-70 % occluded are
      dropped): 99.3 % agreement with the true rule. Read ``occupr`` as the visible share (the rule before
      ``occupr`` followed the real files) and every real car would look 20 % occluded.
    - Truncation: ``truncr < max_truncation`` (``truncr`` is the share outside the image in every format).
    - ``visible_pixels``: the instance's pixel count in the instance map
      (:func:`~sdn3d.data.records.visible_pixel_counts`), ``> min_pixels``.

    The label is not checked: VKITTI's ``DontCare`` follows KITTI's own thresholds, not the paper's.
    """
    return (
        visible_pixels > min_pixels
        and occlusion_estimate(obj) < max_occlusion
        and (obj.occluded is None or obj.occluded < 2)
        and obj.truncr < max_truncation
    )
