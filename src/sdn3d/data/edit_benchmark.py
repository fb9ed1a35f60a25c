"""The 3D-SDN editing benchmark format (``vkitti_edit_benchmark.json``).

A file is a JSON list of entries::

    {"world": "0006", "topic": "fog", "source": "00055", "target": "00050",
     "operations": [
        {"type": "modify", "from": {"u": "750.9", "v": "213.9"},
         "to": {"u": "804.4", "v": "227.1", "roi": [194, 756, 269, 865]},
         "zoom": "1.338", "ry": "0.007"},
        {"type": "delete", "from": {"u": "1328.5", "v": "271.3"}, "to": null, "zoom": null, "ry": null}]}

``topic`` is the Virtual KITTI variation. Numbers may be JSON numbers or strings.
``modify`` moves the object whose projected centre is nearest ``from`` so that it
projects to ``to`` (``{}``/null/absent keeps it), divides its distance by ``zoom``
and adds ``ry`` to its yaw; ``delete`` removes it (``to``, ``zoom``, ``ry`` are null).
``roi`` is ``[top, left, bottom, right]`` in pixels. Coordinates are pixels of the
1242x375 frame (pixel centres at integers). Identity entries (source == target,
no operations) pair every real edit in the shipped file.

An entry may carry ``"kind"``: ``"edit"`` (the default, and every entry of the paper's file) or
``"occluder_removed"`` (this project's synthetic benchmark: a car in front of a partly hidden one is deleted,
and the target shows the hidden car whole; benchmarks report such entries apart). ``"kind"`` is written only
when it is not ``"edit"``, so the paper's format is unchanged.

Validation in :func:`load_edit_benchmark` covers types, finiteness, ``zoom > 0``
and known kinds. It deliberately does NOT check that points lie inside the frame:
the shipped benchmark has ``from`` points outside 1242x375 (e.g. a delete at
u = 1328.5, objects whose centre projects off-screen) and must load as published.
Use :func:`validate_in_frame` where a user types an edit (the editing CLI).

The published file and its example ship with sdn3d (:mod:`sdn3d.resources`);
:func:`benchmark_path` resolves their names (:data:`SHIPPED_BENCHMARKS`, e.g. ``"paper"``)
or a path, as ``sdn3d-bench benchmark=...`` does.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from sdn3d.data.errors import DataFormatError, missing
from sdn3d.io import write_text_atomic

__all__ = [
    "EDIT_KINDS",
    "ENTRY_KINDS",
    "VKITTI_FRAME_SIZE",
    "WORKING_SIZE",
    "BenchmarkOperation",
    "BenchmarkEntry",
    "SHIPPED_BENCHMARKS",
    "benchmark_path",
    "load_edit_benchmark",
    "save_edit_benchmark",
    "scale_point",
    "scale_operation",
    "scale_entry",
    "validate_in_frame",
]

EDIT_KINDS = ("modify", "delete")
#: The largest ``zoom`` an operation may ask (the paper's file: at most about 2); a larger one is a broken file.
MAX_ZOOM = 100.0
#: What a benchmark entry tests (module doc).
ENTRY_KINDS = ("edit", "occluder_removed")
#: (width, height) of the frames the benchmark coordinates refer to.
VKITTI_FRAME_SIZE = (1242, 375)
#: (width, height) the paper works at on Virtual KITTI.
WORKING_SIZE = (624, 192)
#: Names of the benchmark files shipped in :mod:`sdn3d.resources`, for :func:`benchmark_path`.
SHIPPED_BENCHMARKS = {"paper": "vkitti_edit_benchmark.json", "paper_example": "vkitti_edit_example.json"}


def _finite(value: float, what: str) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{what} must be finite, got {value}")
    return value


@dataclass(frozen=True)
class BenchmarkOperation:
    """One edit. Build with :meth:`modify` / :meth:`delete`.

    Attributes:
        kind: ``'modify'`` or ``'delete'``.
        from_uv: ``(u, v)`` pixel picking the object (nearest projected 3D centre).
        to_uv: ``(u, v)`` target projection of the centre; None keeps the position.
        zoom: distance divisor (> 0); None for delete.
        ry: yaw increment in radians; None for delete.
        roi: ``(top, left, bottom, right)`` pixels of the edited object, or None.
    """

    kind: str
    from_uv: tuple[float, float]
    to_uv: tuple[float, float] | None = None
    zoom: float | None = None
    ry: float | None = None
    roi: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        if self.kind not in EDIT_KINDS:
            raise ValueError(f"BenchmarkOperation.kind must be one of {EDIT_KINDS}, got {self.kind!r}")
        for name, size in (("from_uv", 2), ("to_uv", 2), ("roi", 4)):
            value = getattr(self, name)
            if value is None:
                continue
            if len(value) != size:
                raise ValueError(f"BenchmarkOperation.{name} must have {size} values, got {value!r}")
            object.__setattr__(self, name, tuple(_finite(x, f"BenchmarkOperation.{name}") for x in value))
        if self.kind == "modify" and (self.zoom is None or self.ry is None):
            raise ValueError("BenchmarkOperation: a modify needs zoom and ry (use 1.0 and 0.0 for no change)")
        if self.zoom is not None:
            zoom = _finite(self.zoom, "BenchmarkOperation.zoom")
            if zoom <= 0:
                raise ValueError(f"BenchmarkOperation.zoom must be > 0, got {zoom}")
            object.__setattr__(self, "zoom", zoom)
        if self.ry is not None:
            object.__setattr__(self, "ry", _finite(self.ry, "BenchmarkOperation.ry"))
        if self.roi is not None and (self.roi[0] > self.roi[2] or self.roi[1] > self.roi[3]):
            raise ValueError(f"BenchmarkOperation.roi must be (top, left, bottom, right) with top <= bottom "
                             f"and left <= right, got {self.roi}")  # fmt: skip

    @classmethod
    def modify(
        cls,
        from_uv: tuple[float, float],
        to_uv: tuple[float, float] | None = None,
        zoom: float = 1.0,
        ry: float = 0.0,
        roi: tuple[float, float, float, float] | None = None,
    ) -> BenchmarkOperation:
        return cls("modify", from_uv, to_uv, zoom, ry, roi)

    @classmethod
    def delete(cls, from_uv: tuple[float, float]) -> BenchmarkOperation:
        return cls("delete", from_uv)


@dataclass(frozen=True)
class BenchmarkEntry:
    """One benchmark entry: edit ``source_frame`` of ``world/variation`` (target = reference frame)."""

    world: str
    variation: str
    source_frame: int
    target_frame: int
    operations: tuple[BenchmarkOperation, ...] = ()
    kind: str = "edit"

    def __post_init__(self) -> None:
        object.__setattr__(self, "operations", tuple(self.operations))
        if self.kind not in ENTRY_KINDS:
            raise ValueError(f"BenchmarkEntry.kind must be one of {ENTRY_KINDS}, got {self.kind!r}")
        if self.source_frame < 0 or self.target_frame < 0:
            raise ValueError(f"BenchmarkEntry frames must be >= 0, got {self.source_frame}, {self.target_frame}")

    @property
    def is_identity(self) -> bool:
        """True for the benchmark's identity entries (nothing to edit)."""
        return not self.operations


class _Where:
    """Error context: file, entry index and operation index."""

    def __init__(self, path: Path, entry: int, op: int | None = None) -> None:
        self.path, self.entry, self.op = path, entry, op

    def error(self, field: str, problem: str) -> DataFormatError:
        where = f"{self.path}: entry {self.entry}"
        if self.op is not None:
            where += f" operation {self.op}"
        return DataFormatError(f"{where}: field {field!r}: {problem}")

    def number(self, container: dict, key: str, field: str) -> float:
        if key not in container:
            raise self.error(field, "missing")
        value = container[key]
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise self.error(field, f"expected a number or numeric string, got {value!r}")
        try:
            number = float(value)
        except ValueError:
            raise self.error(field, f"expected a number, got {value!r}") from None
        if not math.isfinite(number):
            raise self.error(field, f"expected a finite number, got {value!r}")
        return number


def _parse_operation(raw: Any, where: _Where) -> BenchmarkOperation:
    if not isinstance(raw, dict):
        raise where.error("operations", f"expected an object, got {type(raw).__name__}")
    kind = raw.get("type")
    if kind not in EDIT_KINDS:
        raise where.error("type", f"expected one of {EDIT_KINDS}, got {kind!r}")
    src = raw.get("from")
    if not isinstance(src, dict):
        raise where.error("from", f"expected an object with u and v, got {src!r}")
    from_uv = (where.number(src, "u", "from.u"), where.number(src, "v", "from.v"))
    to_uv = roi = None
    dst = raw.get("to")
    if dst not in (None, {}):
        if not isinstance(dst, dict):
            raise where.error("to", f"expected an object, {{}} or null, got {dst!r}")
        to_uv = (where.number(dst, "u", "to.u"), where.number(dst, "v", "to.v"))
        if dst.get("roi") is not None:
            box = dst["roi"]
            if not isinstance(box, list) or len(box) != 4:
                raise where.error("to.roi", f"expected [top, left, bottom, right], got {box!r}")
            roi = tuple(where.number({"x": x}, "x", f"to.roi[{i}]") for i, x in enumerate(box))
            if roi[0] > roi[2] or roi[1] > roi[3]:
                raise where.error("to.roi", f"expected top <= bottom and left <= right, got {box!r}")
    zoom = ry = None
    if kind == "modify" or raw.get("zoom") is not None:
        zoom = where.number(raw, "zoom", "zoom")
        if zoom <= 0:
            raise where.error("zoom", f"expected a number > 0, got {raw['zoom']!r}")
        if zoom > MAX_ZOOM:
            raise where.error("zoom", f"expected a number <= {MAX_ZOOM:g} (a change of distance), got {raw['zoom']!r}")
    if kind == "modify" or raw.get("ry") is not None:
        ry = where.number(raw, "ry", "ry")
        if abs(ry) > 2 * math.pi:
            raise where.error("ry", f"expected a yaw increment in radians within [-2 pi, 2 pi], got {raw['ry']!r}")
    return BenchmarkOperation(kind, from_uv, to_uv, zoom, ry, roi)


def _parse_frame(raw: dict, key: str, where: _Where) -> int:
    value = where.number(raw, key, key)
    if value < 0 or value != int(value):
        raise where.error(key, f"expected a frame index >= 0, got {raw[key]!r}")
    return int(value)


def _parse_entry(raw: Any, where: _Where) -> BenchmarkEntry:
    if not isinstance(raw, dict):
        raise where.error("entry", f"expected an object, got {type(raw).__name__}")
    for key in ("world", "topic"):
        if not isinstance(raw.get(key), str) or not raw[key]:
            problem = "missing" if key not in raw else f"expected a non-empty string, got {raw[key]!r}"
            raise where.error(key, problem)
    operations = raw.get("operations")
    if not isinstance(operations, list):
        raise where.error("operations", "missing" if "operations" not in raw else "expected a list")
    ops = tuple(_parse_operation(op, _Where(where.path, where.entry, j)) for j, op in enumerate(operations))
    source, target = _parse_frame(raw, "source", where), _parse_frame(raw, "target", where)
    kind = raw.get("kind", "edit")
    if kind not in ENTRY_KINDS:
        raise where.error("kind", f"expected one of {list(ENTRY_KINDS)}, got {kind!r}")
    return BenchmarkEntry(raw["world"], raw["topic"], source, target, ops, kind)


def benchmark_path(benchmark: str | os.PathLike) -> Path:
    """The file of a benchmark given by name or path.

    A name of :data:`SHIPPED_BENCHMARKS` (``"paper"``: the paper's 184-entry file,
    ``"paper_example"``: its 5-entry example) gives the shipped file; anything else is a
    path (``~`` expanded; write ``./paper`` for a file named ``paper``). The file is not
    checked here: :func:`load_edit_benchmark` reports a missing one.
    """
    if isinstance(benchmark, str) and benchmark in SHIPPED_BENCHMARKS:
        from sdn3d.resources import resource_path

        return resource_path(SHIPPED_BENCHMARKS[benchmark])
    return Path(benchmark).expanduser()


def load_edit_benchmark(path: str | os.PathLike) -> list[BenchmarkEntry]:
    """Parse a benchmark JSON file. Errors (``DataFormatError``, a ``ValueError``) name
    the file, the entry index, the operation index and the field."""
    path = Path(path)
    if not path.is_file():
        raise missing(path, "edit benchmark file")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise DataFormatError(
            f"{path}: invalid JSON at line {exc.lineno} column {exc.colno}: {exc.msg}"
        ) from exc
    except UnicodeDecodeError as exc:
        raise DataFormatError(f"{path}: not UTF-8 text ({exc})") from exc
    if not isinstance(data, list):
        raise DataFormatError(f"{path}: expected a JSON list of entries, got {type(data).__name__}")
    return [_parse_entry(raw, _Where(path, i)) for i, raw in enumerate(data)]


def _text(value: float) -> str:
    # Shortest round-tripping decimal, matching the file's string-number style ("750.9").
    return repr(float(value))


def _json_number(value: float) -> int | float:
    return int(value) if float(value).is_integer() else float(value)


def _operation_json(op: BenchmarkOperation) -> dict[str, Any]:
    to: dict[str, Any] | None
    if op.to_uv is None:
        to = None if op.kind == "delete" else {}
    else:
        to = {"u": _text(op.to_uv[0]), "v": _text(op.to_uv[1])}
        if op.roi is not None:
            to["roi"] = [_json_number(x) for x in op.roi]
    return {
        "type": op.kind,
        "from": {"u": _text(op.from_uv[0]), "v": _text(op.from_uv[1])},
        "to": to,
        "zoom": None if op.zoom is None else _text(op.zoom),
        "ry": None if op.ry is None else _text(op.ry),
    }


def save_edit_benchmark(entries: Sequence[BenchmarkEntry], path: str | os.PathLike) -> Path:
    """Write ``entries`` in the benchmark format (4-space indent, numbers as strings,
    frames as ``%05d``), atomically: a temporary file renamed over ``path``."""
    data = [
        {
            "world": entry.world,
            "topic": entry.variation,
            "source": f"{entry.source_frame:05d}",
            "target": f"{entry.target_frame:05d}",
            "operations": [_operation_json(op) for op in entry.operations],
            **({} if entry.kind == "edit" else {"kind": entry.kind}),
        }
        for entry in entries
    ]
    return write_text_atomic(path, json.dumps(data, indent=4) + "\n")


def scale_point(
    uv: tuple[float, float], from_size: tuple[int, int], to_size: tuple[int, int]
) -> tuple[float, float]:
    """Map a pixel coordinate between image sizes ``(width, height)``.

    Pixel centres sit at integers, so ``u' + 0.5 = (u + 0.5) * sx`` exactly as
    :meth:`sdn3d.math3d.camera.Intrinsics.resized` maps the principal point.
    """
    sx, sy = to_size[0] / from_size[0], to_size[1] / from_size[1]
    return ((uv[0] + 0.5) * sx - 0.5, (uv[1] + 0.5) * sy - 0.5)


def scale_operation(
    op: BenchmarkOperation,
    from_size: tuple[int, int] = VKITTI_FRAME_SIZE,
    to_size: tuple[int, int] = WORKING_SIZE,
) -> BenchmarkOperation:
    """``op`` with ``from``/``to``/``roi`` pixel coordinates mapped from ``from_size`` to
    ``to_size`` (both ``(width, height)``); zoom and ry do not depend on image size."""
    for name, size in (("from_size", from_size), ("to_size", to_size)):
        if len(size) != 2 or min(size) <= 0:
            raise ValueError(f"scale_operation: {name} must be (width, height) > 0, got {size!r}")
    roi = None
    if op.roi is not None:
        left, top = scale_point((op.roi[1], op.roi[0]), from_size, to_size)
        right, bottom = scale_point((op.roi[3], op.roi[2]), from_size, to_size)
        roi = (top, left, bottom, right)
    to_uv = None if op.to_uv is None else scale_point(op.to_uv, from_size, to_size)
    return replace(op, from_uv=scale_point(op.from_uv, from_size, to_size), to_uv=to_uv, roi=roi)


def scale_entry(
    entry: BenchmarkEntry,
    from_size: tuple[int, int] = VKITTI_FRAME_SIZE,
    to_size: tuple[int, int] = WORKING_SIZE,
) -> BenchmarkEntry:
    """:func:`scale_operation` applied to every operation of ``entry``."""
    operations = tuple(scale_operation(op, from_size, to_size) for op in entry.operations)
    return replace(entry, operations=operations)


def validate_in_frame(
    entry: BenchmarkEntry,
    size: tuple[int, int] = VKITTI_FRAME_SIZE,
    margin: float = 0.0,
    index: int | None = None,
) -> None:
    """Raise ``ValueError`` if any ``from``/``to`` point lies outside the image.

    The image spans ``[-0.5, W - 0.5] x [-0.5, H - 0.5]``, widened by ``margin`` pixels
    on every side. For user-given edits only; the loader accepts off-frame points
    because the published benchmark contains them (see module doc).

    Args:
        entry: the edit to check.
        size: ``(width, height)`` of the frame the coordinates refer to.
        margin: tolerance in pixels (>= 0).
        index: entry index for the message, if the entry came from a list.
    """
    if margin < 0 or not math.isfinite(margin):
        raise ValueError(f"validate_in_frame: margin must be finite and >= 0, got {margin}")
    width, height = size
    u_range = (-0.5 - margin, width - 0.5 + margin)
    v_range = (-0.5 - margin, height - 0.5 + margin)
    problems = []
    for j, op in enumerate(entry.operations):
        for name, uv in (("from", op.from_uv), ("to", op.to_uv)):
            if uv is None:
                continue
            u, v = uv
            if not (u_range[0] <= u <= u_range[1] and v_range[0] <= v <= v_range[1]):
                problems.append(f"operation {j} ({op.kind}) '{name}' point ({u}, {v})")
    if problems:
        label = f"entry {index}" if index is not None else "edit"
        raise ValueError(
            f"{label} ({entry.world}/{entry.variation} frame {entry.source_frame}): points outside the "
            f"{width}x{height} frame (margin {margin} px): " + "; ".join(problems)
        )
