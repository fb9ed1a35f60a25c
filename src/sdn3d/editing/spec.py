"""Edit specifications typed by a user (``sdn3d-edit``): a YAML list of operations or a benchmark entry.

YAML (a list, or a mapping ``{frame_size: [W, H], ops: [...]}`` when the pixel coordinates refer
to the input image resized to another size)::

    - {op: move, id: 12001, to: [300, 120]}        # slide on the ground so the centre projects to (u, v)
    - {op: rotate, at: [210, 130], ry_deg: 30}     # add 30 degrees to the yaw of the object at pixel (u, v)
    - {op: rotate, id: 12001, ry_rad: 0.5}         # ... or radians, said explicitly (at most 2 pi)
    - {op: zoom, id: 12001, zoom: 1.5}             # distance / 1.5 (on_ground: true keeps its height)
    - {op: delete, at: [400, 110]}
    - {op: recolor, id: 12002, sample: true}       # a training code of its class (needs a code bank)
    - {op: recolor, id: 12002, color: red}         # photo appearance: the car's body repainted red; generator:
                                                   # the training code whose object's colour is nearest red
    - {op: recolor, id: 12002, code: [0.1, -0.2, 0.3, 0.0, 0.5]}
    - {op: recolor, class: Road, code: [...]}      # a background class' code
    - {op: duplicate, id: 12001, to: [500, 130]}   # optional new_id
    - {op: modify, from: [300, 120], to: [350, 125], zoom: 1.2, ry_deg: 15}   # the benchmark's modify

Objects a person names by a box (real photos: no trained segmenter or 3D labels needed) come in the mapping form::

    objects:                                       # GrabCut mask in the box, 3D shape fitted to it
      - {box: [466, 203, 666, 333], class: Car}    # [x0, y0, x1, y1], half-open, the spec's pixels; class: Car
      - {box: [10, 5, 17, 11], force: true}        # added even where nothing says a vehicle is there (else refused)
    ops:                                           # may be empty: then the objects are listed (list=true)
      - {op: rotate, at: [565, 265], ry_deg: 45}

:func:`box_prompts` turns them into the working image's :class:`~sdn3d.derender.BoxPrompts`.

Objects are selected by ``id`` (instance id) or ``at: [u, v]`` (the object visible at that pixel,
else the one whose projected centre is nearest, within ``pick_radius``); ``modify`` also takes
``from`` (nearest projected centre, the benchmark's rule). Picks by position are resolved on the unedited
scene; an ``id`` names an object of the scene as the earlier ops left it: a ``duplicate``'s copy (its id the next
of its class, or ``new_id``) can be moved, turned, recoloured, duplicated or deleted by the later ops. A copy
stands clear of the other cars in 3D (pushed along the road from ``to`` until it does, else refused) and keeps the
original's current look (a recolor before the duplicate included).

Pixel frame: ``sdn3d-edit`` passes a :class:`PixelFrame` (the input image -> working size transform), so
``at`` / ``to`` / ``from`` are pixels of the input image (the image file, or the dataset frame at its stored
size), as ``list=true`` prints them; ``frame_size: [W, H]`` says they are pixels of the input image resized
to ``W x H`` instead. Without a :class:`PixelFrame` (library use) they are the scene's (working-size) pixels,
or ``frame_size`` pixels scaled to it. Error messages show points in the user's frame (0.1 px).
A JSON file is read as a 3D-SDN benchmark (:mod:`sdn3d.data.edit_benchmark`; one entry,
coordinates in 1242x375 pixels by default).

:func:`parse_edit_spec` / :func:`load_edit_spec` check the syntax and the numbers (finite,
``zoom > 0``) without a scene; :func:`resolve_ops` checks everything that needs the scene (the
object exists and has geometry, targets inside the frame, code sizes) and :func:`apply_spec`
applies them. Errors are :class:`EditSpecError` / :class:`~sdn3d.editing.apply.EditError` naming the op.
"""

from __future__ import annotations

import json
import math
import os
import reprlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import torch

from sdn3d.data.edit_benchmark import (
    VKITTI_FRAME_SIZE,
    BenchmarkEntry,
    load_edit_benchmark,
    scale_point,
    validate_in_frame,
)
from sdn3d.derender import BoxPrompts
from sdn3d.editing.apply import (
    Delete,
    Duplicate,
    EditError,
    EditOp,
    Modify,
    Move,
    Rotate,
    SetBackgroundCode,
    SetCode,
    Zoom,
    apply_edits,
    clear_place,
    copy_id,
    edited_table,
    ops_from_benchmark,
)
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import shown_point
from sdn3d.editing.pick import MaskOnlyUnder, pick_objects
from sdn3d.errors import UserInputError
from sdn3d.io import yaml_loader
from sdn3d.meshes.bank import MeshBank
from sdn3d.scene.code import ObjectTable, SceneCode
from sdn3d.scene.maps import compose_instances
from sdn3d.textural.code_bank import named_color
from sdn3d.textural.codes import CodeBank

__all__ = ["OP_KINDS", "EditSpecError", "OpSpec", "EditSpec", "parse_edit_spec", "load_edit_spec", "resolve_ops",
           "apply_spec", "read_yaml", "MAX_OPS", "EXCERPT_CHARS", "BoxObjectSpec", "box_prompts",
           "MAX_BOX_OBJECTS", "code_bank_needed",
           "check_points", "box_object_ids", "check_ids"]

OP_KINDS = ("move", "rotate", "zoom", "delete", "recolor", "duplicate", "modify")
_FIELDS = {"move": {"to"}, "rotate": {"ry_deg", "ry_rad"}, "zoom": {"zoom", "on_ground"}, "delete": set(),
           "recolor": {"code", "sample", "color", "seed", "class"}, "duplicate": {"to", "new_id"},
           "modify": {"to", "zoom", "ry_deg", "ry_rad", "from"}}
_GEOMETRIC = ("move", "rotate", "zoom", "duplicate", "modify")


class EditSpecError(UserInputError):
    """A malformed edit specification (message names the file, the op and the field)."""


@dataclass(frozen=True)
class OpSpec:
    """One parsed operation (not yet resolved against a scene); see the module doc for the fields."""

    index: int
    kind: str
    id: int | None = None
    at: tuple[float, float] | None = None
    from_uv: tuple[float, float] | None = None
    class_: int | str | None = None
    to: tuple[float, float] | None = None
    ry: float = 0.0
    zoom: float = 1.0
    on_ground: bool = False
    code: tuple[float, ...] | None = None
    sample: bool = False
    color: str | None = None
    seed: int | None = None
    new_id: int | None = None

    def describe(self) -> str:
        """E.g. ``op 2 (move id=12001)``."""
        if self.id is not None:
            who = f"id={self.id}"
        elif self.at is not None:
            who = f"at={list(self.at)}"
        elif self.from_uv is not None:
            who = f"from={list(self.from_uv)}"
        else:
            who = f"class={self.class_}"
        return f"op {self.index} ({self.kind} {who})"


@dataclass(frozen=True)
class BoxObjectSpec:
    """One object named by a box: ``box`` half-open ``(x0, y0, x1, y1)`` in the spec's pixels, its ``class_``;
    ``force``: added even where GrabCut, the road plane and the fit say no vehicle is there
    (:func:`sdn3d.box_masks.no_vehicle`; otherwise such a box is refused)."""

    index: int
    box: tuple[float, float, float, float]
    class_: str | int = "Car"
    force: bool = False


@dataclass(frozen=True)
class EditSpec:
    """Parsed edits: user ``ops`` or a benchmark ``entry``, with the ``frame_size (W, H)`` their pixel
    coordinates refer to (None: the scene's own pixels), and ``objects`` named by a box."""

    ops: tuple[OpSpec, ...] = ()
    entry: BenchmarkEntry | None = None
    frame_size: tuple[int, int] | None = None
    source: str = "<edit spec>"
    objects: tuple[BoxObjectSpec, ...] = ()

    def __len__(self) -> int:
        return len(self.entry.operations) if self.entry is not None else len(self.ops)


#: Longest excerpt of a user's value quoted in an error message (a value may be megabytes long).
EXCERPT_CHARS = 80
#: Default cap on the number of operations of one edit spec (``sdn3d-edit``'s ``max_ops``).
MAX_OPS = 256
#: The most objects an edit spec may name by a box (each costs a GrabCut and a 3D fit, about a second).
MAX_BOX_OBJECTS = 64

_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxtuple, _REPR.maxdict, _REPR.maxset = 3, 6, 6, 4, 4
_REPR.maxstring, _REPR.maxother, _REPR.maxlong = EXCERPT_CHARS, EXCERPT_CHARS, 40


def _excerpt(value: Any, limit: int = EXCERPT_CHARS) -> str:
    """``repr(value)`` cut to at most ``limit`` characters (nested and long values abridged without being
    expanded whole): what an error message quotes of a user's value."""
    try:
        text = _REPR.repr(value)
    except (ValueError, RecursionError):  # e.g. an integer over Python's 4300-digit str limit
        text = f"<a {type(value).__name__} too long to show>"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def read_yaml(path: str | os.PathLike, what: str = "edit spec") -> Any:
    """The content of the YAML file ``path`` (safe loading), refusing anchors and aliases (``&a`` / ``*a``):
    a few hundred bytes of nested aliases expand to gigabytes (a "billion laughs" file), and an edit spec
    has no use for them. The document is checked event by event before anything is built.

    Raises:
        EditSpecError: naming the file: invalid YAML, an anchor or alias (with its line), not UTF-8.
    """
    import yaml

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise EditSpecError(f"{path}: {what} is not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    loader = yaml_loader()
    try:
        for event in yaml.parse(text, Loader=loader):
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None) is not None:
                line = event.start_mark.line + 1 if event.start_mark is not None else "?"
                raise EditSpecError(f"{path}:{line}: {what}: YAML anchors and aliases (&name, *name) are not "
                                    "accepted; write each value out")
        return yaml.load(text, Loader=loader)  # noqa: S506 (a safe loader)
    except EditSpecError:
        raise
    except yaml.YAMLError as exc:
        raise EditSpecError(f"{path}: invalid YAML ({_excerpt(str(exc), 400)})") from None
    except (ValueError, RecursionError) as exc:  # a constructor's failure (an integer of 10^5 digits, deep nesting)
        raise EditSpecError(f"{path}: {what} holds a value that cannot be read ({_excerpt(str(exc))})") from None


def _number(value: Any, what: str) -> float:
    """A finite float; a string ``float()`` reads is a number too (PyYAML, following YAML 1.1, reads
    ``1e9`` and ``1.0e9`` as strings: its float pattern needs a dot and a signed exponent)."""
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            raise EditSpecError(f"{what} must be a number, got {_excerpt(value)}") from None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise EditSpecError(f"{what} must be a number, got {_excerpt(value)}")
    try:
        number = float(value)
    except OverflowError:  # an integer too large for a float (10**400)
        raise EditSpecError(f"{what} must be finite, got an integer of {len(str(abs(value)))} digits") from None
    if not math.isfinite(number):
        raise EditSpecError(f"{what} must be finite, got {_excerpt(value)}")
    return number


def _point(value: Any, what: str) -> tuple[float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise EditSpecError(f"{what} must be a pixel [u, v], got {_excerpt(value)}")
    return (_number(value[0], f"{what}[0]"), _number(value[1], f"{what}[1]"))


def _int(value: Any, what: str, minimum: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise EditSpecError(f"{what} must be an integer >= {minimum}, got {_excerpt(value)}")
    return int(value)


def _parse_op(raw: Any, index: int, where: str) -> OpSpec:
    if not isinstance(raw, Mapping):
        raise EditSpecError(f"{where}: op {index} must be a mapping like {{op: move, id: 12001, to: [u, v]}}, "
                            f"got {_excerpt(raw)}")
    kind = raw.get("op")
    if not isinstance(kind, str) or kind.lower() not in OP_KINDS:
        raise EditSpecError(f"{where}: op {index}: field 'op' must be one of {OP_KINDS}, got {_excerpt(kind)}")
    kind = kind.lower()
    name = f"{where}: op {index} ({kind})"
    if "ry" in raw and kind in ("rotate", "modify"):
        raise EditSpecError(f"{name}: field 'ry' has no unit: write the angle added to the yaw as ry_deg (degrees, "
                            f"e.g. ry_deg: 45) or ry_rad (radians, e.g. ry_rad: 0.785)")
    unknown = set(raw) - {"op", "id", "at"} - _FIELDS[kind]
    if unknown:
        raise EditSpecError(f"{name}: unknown field(s) {_excerpt(sorted(map(str, unknown)))}; allowed: "
                            f"{sorted({'op', 'id', 'at'} | _FIELDS[kind])}")
    selectors = [k for k in ("id", "at", "from", "class") if k in raw]
    if len(selectors) != 1:
        raise EditSpecError(f"{name}: select the object with exactly one of 'id' or 'at'"
                            + (" (or 'class' for a background class)" if kind == "recolor" else "")
                            + (" (or 'from')" if kind == "modify" else "") + f", got {selectors or 'none'}")
    fields: dict[str, Any] = {}
    if "id" in raw:
        fields["id"] = _int(raw["id"], f"{name}: field 'id'", 1000)
    if "at" in raw:
        fields["at"] = _point(raw["at"], f"{name}: field 'at'")
    if "from" in raw:
        fields["from_uv"] = _point(raw["from"], f"{name}: field 'from'")
    if "class" in raw:
        if isinstance(raw["class"], bool) or not isinstance(raw["class"], (int, str)):
            raise EditSpecError(f"{name}: field 'class' must be a class name or id, got {_excerpt(raw['class'])}")
        fields["class_"] = raw["class"]
    if kind in ("move", "duplicate") and raw.get("to") is None:
        raise EditSpecError(f"{name}: field 'to' (target pixel [u, v]) is required")
    if raw.get("to") is not None:
        fields["to"] = _point(raw["to"], f"{name}: field 'to'")
    if "ry_deg" in raw and "ry_rad" in raw:
        raise EditSpecError(f"{name}: give the angle once, as ry_deg or as ry_rad, not both")
    if kind == "rotate" and "ry_deg" not in raw and "ry_rad" not in raw:
        raise EditSpecError(f"{name}: field 'ry_deg' (degrees added to the yaw) or 'ry_rad' (radians) is required")
    if "ry_deg" in raw:
        degrees = _number(raw["ry_deg"], f"{name}: field 'ry_deg'")
        if abs(degrees) > 360:
            raise EditSpecError(f"{name}: field 'ry_deg' is {_excerpt(raw['ry_deg'])} degrees, more than a full turn "
                                "(360): give the angle added to the yaw within [-360, 360]")
        fields["ry"] = math.radians(degrees)
    if "ry_rad" in raw:
        ry = _number(raw["ry_rad"], f"{name}: field 'ry_rad'")
        if abs(ry) > 2 * math.pi:
            raise EditSpecError(f"{name}: field 'ry_rad' is {_excerpt(raw['ry_rad'])} radians, more than a full turn "
                                f"(2 pi): did you mean ry_deg: {_excerpt(raw['ry_rad'])}?")
        fields["ry"] = ry
    if kind == "zoom" and "zoom" not in raw:
        raise EditSpecError(f"{name}: field 'zoom' (distance divisor > 0) is required")
    if "zoom" in raw:
        zoom = _number(raw["zoom"], f"{name}: field 'zoom'")
        if zoom <= 0:
            raise EditSpecError(f"{name}: field 'zoom' must be > 0, got {_excerpt(raw['zoom'])}")
        fields["zoom"] = zoom
    if "on_ground" in raw:
        if not isinstance(raw["on_ground"], bool):
            raise EditSpecError(f"{name}: field 'on_ground' must be true or false, got {_excerpt(raw['on_ground'])}")
        fields["on_ground"] = raw["on_ground"]
    if kind == "recolor":
        has_code, sample, has_color = "code" in raw, raw.get("sample", False), "color" in raw
        if not isinstance(sample, bool) or has_code + bool(sample) + has_color != 1:
            raise EditSpecError(f"{name}: give exactly one of 'code: [...]', 'sample: true' or 'color: <name>'")
        if has_color:
            if not isinstance(raw["color"], str):
                raise EditSpecError(f"{name}: field 'color' must be a colour name, e.g. red, got "
                                    f"{_excerpt(raw['color'])}")
            if len(raw["color"]) > EXCERPT_CHARS:
                raise EditSpecError(f"{name}: field 'color' is {len(raw['color'])} characters long, not a colour "
                                    f"name: {_excerpt(raw['color'])}")
            try:
                named_color(raw["color"], f"{name}: field 'color'")
            except UserInputError as exc:
                raise EditSpecError(str(exc)) from None
            fields["color"] = raw["color"]
        if has_code:
            code = raw["code"]
            if not isinstance(code, (list, tuple)) or not code:
                raise EditSpecError(f"{name}: field 'code' must be a non-empty list of numbers, got {_excerpt(code)}")
            fields["code"] = tuple(_number(c, f"{name}: field 'code[{i}]'") for i, c in enumerate(code))
        fields["sample"] = bool(sample)
        if "seed" in raw:
            fields["seed"] = _int(raw["seed"], f"{name}: field 'seed'")
    if "new_id" in raw and raw["new_id"] is not None:
        fields["new_id"] = _int(raw["new_id"], f"{name}: field 'new_id'", 1000)
    return OpSpec(index, kind, **fields)


def _parse_object(raw: Any, index: int, where: str) -> BoxObjectSpec:
    name = f"{where}: objects[{index}]"
    if not isinstance(raw, Mapping) or "box" not in raw:
        raise EditSpecError(f"{name} must be a mapping like {{box: [x0, y0, x1, y1], class: Car}}, got {_excerpt(raw)}")
    unknown = set(raw) - {"box", "class", "force"}
    if unknown:
        raise EditSpecError(f"{name}: unknown field(s) {_excerpt(sorted(map(str, unknown)))}; "
                            "allowed: ['box', 'class', 'force']")
    force = raw.get("force", False)
    if not isinstance(force, bool):
        raise EditSpecError(f"{name}: field 'force' must be true or false, got {_excerpt(force)}")
    box = raw["box"]
    if not isinstance(box, (list, tuple)) or len(box) != 4:
        raise EditSpecError(f"{name}: field 'box' must be [x0, y0, x1, y1] in pixels, got {_excerpt(box)}")
    x0, y0, x1, y1 = (_number(v, f"{name}: field 'box'[{i}]") for i, v in enumerate(box))
    if not (x1 - x0 >= 2 and y1 - y0 >= 2):
        raise EditSpecError(f"{name}: field 'box' must have x1 >= x0 + 2 and y1 >= y0 + 2 (half-open pixel edges), "
                            f"got {_excerpt(box)}")
    cls = raw.get("class", "Car")
    if isinstance(cls, bool) or not isinstance(cls, (int, str)):
        raise EditSpecError(f"{name}: field 'class' must be a class name or id, got {_excerpt(cls)}")
    return BoxObjectSpec(index, (x0, y0, x1, y1), cls, force)


def parse_edit_spec(data: Any, source: str = "<edit spec>", max_ops: int | None = MAX_OPS) -> EditSpec:
    """Check a YAML-style spec (a list of ops, or ``{frame_size: [W, H], objects: [...], ops: [...]}``); see the
    module doc. A spec with ``objects`` may have no ops (it lists them).

    ``max_ops``: the most operations accepted (None: no limit); every op costs a pass over the scene.
    """
    frame_size = None
    objects: tuple[BoxObjectSpec, ...] = ()
    if isinstance(data, Mapping):
        unknown = set(data) - {"ops", "frame_size", "objects"}
        if unknown or ("ops" not in data and "objects" not in data):
            raise EditSpecError(f"{source}: a mapping spec needs 'ops' and/or 'objects' (and optionally "
                                f"'frame_size'), got keys {_excerpt(sorted(map(str, data)))}")
        if data.get("frame_size") is not None:
            size = data["frame_size"]
            if not isinstance(size, (list, tuple)) or len(size) != 2:
                raise EditSpecError(f"{source}: frame_size must be [W, H], got {_excerpt(size)}")
            frame_size = (_int(size[0], f"{source}: frame_size[0]", 1), _int(size[1], f"{source}: frame_size[1]", 1))
        if data.get("objects") is not None:
            given = data["objects"]
            if not isinstance(given, (list, tuple)):
                raise EditSpecError(f"{source}: objects must be a list of {{box: [x0, y0, x1, y1], class: Car}}, "
                                    f"got {_excerpt(given)}")
            if len(given) > MAX_BOX_OBJECTS:
                raise EditSpecError(f"{source}: {len(given)} objects by box, more than {MAX_BOX_OBJECTS}")
            objects = tuple(_parse_object(raw, i, source) for i, raw in enumerate(given))
        data = data.get("ops")
        if objects and (data is None or (isinstance(data, (list, tuple)) and not data)):
            return EditSpec((), None, frame_size, source, objects)
    if not isinstance(data, (list, tuple)) or not data:
        raise EditSpecError(f"{source}: expected a non-empty list of edit operations, got {_excerpt(data)}")
    if max_ops is not None and len(data) > max_ops:
        raise EditSpecError(f"{source}: {len(data)} edit operations, more than max_ops={max_ops} (sdn3d-edit's "
                            "max_ops setting, conf/edit.yaml): split the edit or raise max_ops")
    return EditSpec(tuple(_parse_op(raw, i, source) for i, raw in enumerate(data)), None, frame_size, source,
                    objects)


def box_prompts(spec: EditSpec, working_size: tuple[int, int], frame: PixelFrame | None = None, *,
                fit: Any = None, prior: bool = False, iterations: int = 5,
                refine_masks: bool = True) -> BoxPrompts | None:
    """The spec's ``objects`` as :class:`~sdn3d.derender.BoxPrompts` in the working image's pixels (None: none).

    A box's edges go through the same transform as ``at`` / ``to`` points (``frame``, ``frame_size``); a box is
    clipped to the working image (a crop of the input may cut it).

    Raises:
        EditSpecError: naming the object, when its box lies outside the working image or is under 2 px there.
    """
    if not spec.objects:
        return None
    width, height = working_size
    boxes = []
    for obj in spec.objects:
        x0, y0, x1, y1 = obj.box
        a = _to_working((x0 - 0.5, y0 - 0.5), spec, working_size, frame)
        b = _to_working((x1 - 0.5, y1 - 0.5), spec, working_size, frame)
        box = [min(max(a[0] + 0.5, 0.0), width), min(max(a[1] + 0.5, 0.0), height),
               min(max(b[0] + 0.5, 0.0), width), min(max(b[1] + 0.5, 0.0), height)]
        if box[2] - box[0] < 2 or box[3] - box[1] < 2:
            raise EditSpecError(f"{spec.source}: objects[{obj.index}]: box {_excerpt(list(obj.box))} lies outside the "
                                f"working image or is under 2 px there ({width}x{height}, working pixels "
                                f"{[round(v, 1) for v in box]})")
        boxes.append(box)
    return BoxPrompts(torch.tensor(boxes), tuple(obj.class_ for obj in spec.objects), fit, prior, iterations,
                      refine_masks=refine_masks)


def load_edit_spec(path: str | os.PathLike, entry: int = 0, frame_size: tuple[int, int] | None = None,
                   strict: bool = True, max_ops: int | None = MAX_OPS) -> EditSpec:
    """Read a YAML ops file, or a benchmark JSON file's ``entry`` (``.json``).

    Args:
        frame_size: override the coordinates' frame (default: the YAML's ``frame_size`` or the scene's
            pixels; for a benchmark, 1242x375).
        strict: benchmark ``from`` / ``to`` points must lie inside the frame.
        max_ops: the most operations a YAML spec may hold (:func:`parse_edit_spec`); YAML anchors and aliases
            are refused (:func:`read_yaml`).
    """
    path = Path(path).expanduser()
    if not path.is_file():
        raise EditSpecError(f"edit spec {str(path)!r} not found")
    if path.suffix.lower() == ".json":
        text = path.read_text(encoding="utf-8")
        try:
            looks_benchmark = isinstance(json.loads(text), list) and all(
                isinstance(e, Mapping) and "operations" in e for e in json.loads(text))
        except json.JSONDecodeError as exc:
            raise EditSpecError(f"{path}: invalid JSON ({exc})") from exc
        if looks_benchmark:
            try:
                entries = load_edit_benchmark(path)
            except ValueError as exc:
                raise EditSpecError(str(exc)) from exc
            if not 0 <= entry < len(entries):
                raise EditSpecError(f"{path}: entry {entry} does not exist (the file has {len(entries)} entries)")
            chosen = entries[entry]
            if chosen.is_identity:
                raise EditSpecError(f"{path}: entry {entry} has no operations (an identity entry)")
            size = tuple(frame_size) if frame_size is not None else VKITTI_FRAME_SIZE
            if strict:
                try:
                    validate_in_frame(chosen, size, index=entry)
                except ValueError as exc:
                    raise EditSpecError(f"{path}: {exc}") from exc
            return EditSpec((), chosen, size, f"{path} entry {entry}")
        data = json.loads(text)
    else:
        data = read_yaml(path)
    spec = parse_edit_spec(data, str(path), max_ops)
    if frame_size is not None:
        spec = EditSpec(spec.ops, None, (int(frame_size[0]), int(frame_size[1])), spec.source, spec.objects)
    return spec


# -- resolution against a scene ---------------------------------------------------------------


def _scaled(uv: tuple[float, float] | None, spec: EditSpec, scene: SceneCode,
            frame: PixelFrame | None = None) -> tuple[float, float] | None:
    """A spec point in the scene's (working) pixels: through ``frame`` (input pixels, or ``frame_size``
    pixels of the resized input), else ``frame_size`` pixels scaled to the scene (None: the scene's own)."""
    return None if uv is None else _to_working(uv, spec, tuple(scene.image_size), frame)


def _to_working(uv: tuple[float, float], spec: EditSpec, working_size: tuple[int, int],
                frame: PixelFrame | None) -> tuple[float, float]:
    """:func:`_scaled` for a working image of ``working_size (W, H)``."""
    if frame is None or (spec.frame_size is not None and frame.is_plain_resize):
        if spec.frame_size is None or tuple(spec.frame_size) == tuple(working_size):
            return uv
        return scale_point(uv, tuple(spec.frame_size), tuple(working_size))
    if spec.frame_size is not None and tuple(spec.frame_size) != tuple(frame.input_size):
        uv = scale_point(uv, tuple(spec.frame_size), tuple(frame.input_size))
    return frame.to_working(uv)


def _user_frame(spec: EditSpec, scene: SceneCode, frame: PixelFrame | None) -> tuple[int, int]:
    """The size of the frame the spec's points are given in."""
    if spec.frame_size is not None:
        return tuple(spec.frame_size)
    return tuple(frame.input_size) if frame is not None else tuple(scene.image_size)


def _unscaled(uv: tuple[float, float], spec: EditSpec, scene: SceneCode,
              frame: PixelFrame | None) -> tuple[float, float]:
    """The inverse of :func:`_scaled` (a working pixel in the user's frame), for messages."""
    if frame is None or (spec.frame_size is not None and frame.is_plain_resize):
        size = _user_frame(spec, scene, frame)
        return uv if tuple(size) == tuple(scene.image_size) else scale_point(uv, scene.image_size, size)
    back = frame.to_input(uv)
    if spec.frame_size is not None and tuple(spec.frame_size) != tuple(frame.input_size):
        back = scale_point(back, tuple(frame.input_size), tuple(spec.frame_size))
    return back


def _inside(uv: tuple[float, float], scene: SceneCode) -> bool:
    width, height = scene.image_size
    return -0.5 <= uv[0] <= width - 0.5 and -0.5 <= uv[1] <= height - 0.5


def _class_id(value: int | str, scene: SceneCode, what: str) -> int:
    names = {c.name.lower(): c.id for c in scene.class_list}
    if isinstance(value, str):
        if value.lower() not in names:
            raise EditError(f"{what}: unknown class {_excerpt(value)}; classes: {[c.name for c in scene.class_list]}")
        return names[value.lower()]
    if not 0 <= int(value) < len(scene.class_list):
        raise EditError(f"{what}: class id {value} is outside [0, {len(scene.class_list)})")
    return int(value)


def _check_inside(op: OpSpec, points: tuple, spec: EditSpec, scene: SceneCode, frame: PixelFrame | None) -> None:
    """Raise naming the op and the point (in the user's pixels) when one of ``points`` (``at``, ``from``, ``to``
    in scene pixels, None where not given) lies outside the working image."""
    for name, uv, given in zip(("at", "from", "to"), points, (op.at, op.from_uv, op.to), strict=True):
        if uv is not None and not _inside(uv, scene):
            fw, fh = _user_frame(spec, scene, frame)
            where = f"the {fw}x{fh} frame"
            if frame is not None and not frame.is_plain_resize:
                (x0, y0), (x1, y1) = (shown_point(_unscaled(c, spec, scene, frame)) for c in
                                      ((-0.5, -0.5), (scene.image_size[0] - 0.5, scene.image_size[1] - 0.5)))
                where = f"the part of the {fw}x{fh} frame the working image keeps (x {x0}..{x1}, y {y0}..{y1})"
            raise EditError(f"{op.describe()}: '{name}' point {shown_point(given)} lies outside {where}")


def check_points(spec: EditSpec, working_size: tuple[int, int], frame: PixelFrame | None = None) -> None:
    """:func:`resolve_ops`' check of the ops' points (``at``, ``from``, ``to`` inside the working image), before any
    scene: ``sdn3d-edit`` calls it before loading a model.

    Raises:
        EditError: naming the op and the point, as :func:`resolve_ops` would after the de-render.
    """
    if spec.entry is not None:
        return
    size = _Size(tuple(working_size))
    for op in spec.ops:
        points = tuple(None if uv is None else _to_working(uv, spec, size.image_size, frame)
                       for uv in (op.at, op.from_uv, op.to))
        _check_inside(op, points, spec, size, frame)


@dataclass(frozen=True)
class _Size:
    """What :func:`_check_inside` reads of a scene: its working size."""

    image_size: tuple[int, int]


def box_object_ids(class_ids: Sequence[int], taken: Sequence[int] = ()) -> list[int]:
    """The instance ids the objects named by a box get (:func:`sdn3d.derender.derender`): in the boxes' order, the
    next free number of each box's class (``class_ids``) after the ids ``taken`` by other proposals."""
    out: list[int] = []
    for cid in class_ids:
        used = [int(i) for i in [*taken, *out] if int(i) // 1000 == int(cid)]
        out.append(int(cid) * 1000 + (max(used) % 1000 if used else 0) + 1)
    return out


def check_ids(spec: EditSpec, ids: Sequence[int], what: str = "") -> None:
    """Check the ops' ``id`` fields against the objects ``ids`` the scene will have, before it exists (with
    ``proposals=boxes`` they are the boxes' :func:`box_object_ids`): ids the earlier ops create (a duplicate's copy)
    count; ids they delete do not. Stops at the first op whose result is unknown without the scene (a duplicate of
    an object picked by position, whose copy's id depends on its class).

    Raises:
        EditError: naming the op, the id and the ids there are (``what``: where they come from).
    """
    if spec.entry is not None:
        return
    live = {int(i): int(i) // 1000 for i in ids}
    for op in spec.ops:
        if op.id is not None and op.id not in live:
            raise EditError(f"{op.describe()}: no object with id {op.id} (the scene will have {sorted(live)}"
                            f"{what})")
        if op.kind == "delete" and op.id is not None:
            del live[op.id]
        elif op.kind == "duplicate":
            if op.id is None and op.new_id is None:
                return
            cls = live[op.id] if op.id is not None else op.new_id // 1000
            new = op.new_id if op.new_id is not None else cls * 1000 + max(i % 1000 for i in live if live[i] == cls) + 1
            live[new] = cls
        elif op.kind == "delete":  # by position: which object is gone is known only with the scene
            return


def resolve_ops(spec: EditSpec, scene: SceneCode, code_bank: CodeBank | None = None,
                pick_radius: float | None = 16.0, bank: MeshBank | None = None, strict: bool = True,
                generator: torch.Generator | None = None, frame: PixelFrame | None = None) -> list[EditOp]:
    """Turn ``spec`` into :mod:`sdn3d.editing.apply` operations on ``scene`` (every check that needs the scene).

    Args:
        code_bank: training codes (and their objects' colours) for ``recolor`` with ``sample`` or ``color``.
        pick_radius: pixels (scene size) a pick by position may be from the object's projected centre.
        strict: benchmark ``to`` points must lie inside the frame.
        generator: randomness of ``sample`` (an op's ``seed`` overrides it).
        frame: the input image -> scene transform; the spec's points are then input-image pixels (or
            ``frame_size`` pixels of the resized input). None: the scene's pixels (or ``frame_size``'s).

    Raises:
        EditError: naming the op: no such object, an object without geometry for a 3D edit, a target
            outside the frame, a code of the wrong size, no code bank or no codes of the class.
    """
    if spec.entry is not None:
        try:
            return ops_from_benchmark(spec.entry, scene, spec.frame_size, strict, pick_radius)
        except EditError as exc:
            raise EditError(f"{spec.source}: {exc}") from None
    obj = scene.objects
    by_position = any(op.id is None and (op.at is not None or op.from_uv is not None) for op in spec.ops)
    instance_map = compose_instances(scene, bank).cpu() if by_position else None
    ops: list[EditOp] = []
    # The objects as the ops so far left them (ids, poses, codes; no rendering): an id an earlier op created (a
    # duplicate's copy) is valid for the later ops, one it deleted is not. Picks by position use the unedited scene.
    table, codes = obj, scene.background_codes
    made: dict[int, str] = {}  # id -> the op that created or deleted it, for messages
    paint: dict[int, tuple[float, float, float]] = {}  # id -> the colour a recolor gave it (carried by its copies)
    for op in spec.ops:
        what = op.describe()
        at, frm, to = (_scaled(op.at, spec, scene, frame), _scaled(op.from_uv, spec, scene, frame),
                       _scaled(op.to, spec, scene, frame))
        _check_inside(op, (at, frm, to), spec, scene, frame)
        added: list[EditOp] = []
        if op.kind == "recolor" and op.class_ is not None:
            cls = _class_id(op.class_, scene, what)
            added.append(SetBackgroundCode(cls, _code(op, cls, scene, code_bank, generator, what)))
        else:
            need_geo = op.kind in _GEOMETRIC
            if op.id is not None:
                if not bool((table.instance_id == op.id).any()):
                    gone = f"; {made[op.id]}" if op.id in made else ""
                    raise EditError(f"{what}: no object with id {op.id}{gone} (the scene has "
                                    f"{table.instance_id.tolist()})")
                iid = op.id
            else:  # by position: ``at``, or a modify's ``from``
                try:
                    iid = pick_objects(scene, [at if at is not None else frm], [need_geo], pick_radius,
                                       instance_map=instance_map, bank=bank,
                                       to_user=lambda uv: _unscaled(uv, spec, scene, frame),
                                       shown=[op.at if at is not None else op.from_uv],
                                       mask_only=MaskOnlyUnder.REFUSE if at is not None else MaskOnlyUnder.PASS_OVER)[0]
                except EditError as exc:
                    raise EditError(f"{what}: {exc}") from None
            if not bool((table.instance_id == iid).any()):
                raise EditError(f"{what}: object {iid} is no longer in the scene: {made.get(iid, 'an earlier op')}")
            row = table.index_of(iid)
            if need_geo and not bool(table.has_geometry[row]):
                raise EditError(f"{what}: object {iid} has no 3D geometry (mask only); it can only be deleted or "
                                "recoloured")
            if op.kind == "move":
                added.append(Move(iid, to))
            elif op.kind == "rotate":
                added.append(Rotate(iid, op.ry))
            elif op.kind == "zoom":
                added.append(Zoom(iid, op.zoom, op.on_ground))
            elif op.kind == "delete":
                added.append(Delete(iid))
                made[iid] = f"{what} deleted it"
            elif op.kind == "duplicate":
                try:
                    added.extend(_duplicate_ops(op, iid, row, to, table, scene, paint, spec, frame, what))
                except EditError as exc:  # where the copy lands (a target above the horizon): name the op
                    if str(exc).startswith(what):
                        raise
                    raise EditError(f"{what}: {exc}") from None
                made[added[0].new_id] = f"{what} made it"
            elif op.kind == "modify":
                added.append(Modify(iid, to, op.zoom, op.ry))
            else:
                code = _set_code(op, iid, None, scene, code_bank, generator, what, table.code[row],
                                 int(table.class_id[row]))
                if code.color is not None:
                    paint[iid] = code.color
                added.append(code)
        for new in added:
            try:
                table, codes = edited_table(scene, table, codes, new)
            except EditError as exc:
                raise EditError(f"{what}: {exc}") from None
        ops.extend(added)
    return ops


def _set_code(op: OpSpec, iid: int, row: int | None, scene: SceneCode, code_bank: CodeBank | None,
              generator: torch.Generator | None, what: str, current: torch.Tensor | None = None,
              class_id: int | None = None) -> SetCode:
    """A ``recolor`` of an object: its code (:func:`_code`) and, for ``color``, the paint. Without a code bank a
    named colour keeps the object's code (``current``: its code now; default its row's in ``scene``; an appearance
    that draws codes refuses it: :func:`code_bank_needed`). ``row`` None: an object an earlier op created."""
    color = named_color(op.color) if op.color is not None else None
    if current is None:
        current = scene.objects.code[row]
    if class_id is None:
        class_id = int(scene.objects.class_id[row]) if row is not None else None
    if color is not None and code_bank is None:
        return SetCode(iid, tuple(float(c) for c in current), color)
    return SetCode(iid, _code(op, class_id, scene, code_bank, generator, what), color)


def _duplicate_ops(op: OpSpec, iid: int, row: int, to: tuple[float, float], table: ObjectTable, scene: SceneCode,
                   paint: dict[int, tuple[float, float, float]], spec: EditSpec, frame: PixelFrame | None,
                   what: str) -> list[EditOp]:
    """A ``duplicate`` of the object at ``table``'s row ``row`` (the objects as the earlier ops left them): the copy
    gets its id here (``new_id``, else the next of its class, so later ops can name it), stands clear of every other
    car in 3D (:func:`~sdn3d.editing.apply.clear_place`: pushed along the road from ``to`` until its footprint
    clears; refused when nothing in the picture does) and carries the original's current appearance (its code, and
    the colour a recolor gave it)."""
    new_id = op.new_id if op.new_id is not None else copy_id(table, row)
    place, pushed, blocker = clear_place(scene, table, row, to)
    if blocker is not None:
        raise EditError(f"{what}: the copy at {shown_point(op.to)} would overlap object {blocker} in 3D, and no place "
                        "along the road within three car lengths (inside the picture) is clear of the other cars; give "
                        "another 'to'")
    out: list[EditOp] = [Duplicate(iid, place, new_id)]
    if iid in paint:
        out.append(SetCode(new_id, tuple(float(c) for c in table.code[row]), paint[iid]))
        paint[new_id] = paint[iid]
    return out


def _no_code_bank(what: str, field: str) -> EditError:
    return EditError(f"{what}: {field} needs a code bank of training codes (code_bank=<file>; sdn3d-train writes "
                     "<checkpoint>.code_bank.json next to the textural checkpoint)")


def code_bank_needed(spec: EditSpec, code_bank: CodeBank | None) -> None:
    """For an appearance that draws texture codes (the generator): raises the :class:`EditError` naming the first
    ``recolor`` of an object by ``color`` when there is no code bank to pick its code from (:func:`resolve_ops`
    then keeps the object's code, which only the photo appearance repaints)."""
    if code_bank is not None:
        return
    for op in spec.ops:
        if op.kind == "recolor" and op.class_ is None and op.color is not None:
            raise _no_code_bank(op.describe(), f"'color: {op.color}'")


def _code(op: OpSpec, class_id: int, scene: SceneCode, code_bank: CodeBank | None,
          generator: torch.Generator | None, what: str) -> tuple[float, ...]:
    """The code an op gives: its own ``code``, a bank code drawn (``sample``) or picked by ``color``."""
    if op.code is not None:
        if len(op.code) != scene.code_dim:
            raise EditError(f"{what}: code has {len(op.code)} values, the scene's texture codes have {scene.code_dim}")
        return op.code
    field = f"'color: {op.color}'" if op.color is not None else "'sample: true'"
    if code_bank is None:
        raise _no_code_bank(what, field)
    if op.seed is not None:
        generator = torch.Generator().manual_seed(op.seed)
    try:
        if op.color is None:
            code = code_bank.sample(class_id, 1, generator)[0]
        elif code_bank.colors is None:
            raise EditError(f"{what}: {field} needs a code bank with its objects' colours; this one has codes only")
        else:
            code = code_bank.nearest(class_id, torch.tensor(named_color(op.color)))[0]
    except KeyError as exc:
        raise EditError(f"{what}: {exc.args[0]}") from None
    if code.numel() != scene.code_dim:
        raise EditError(f"{what}: the code bank's codes have {code.numel()} values, the scene's {scene.code_dim}")
    return tuple(float(c) for c in code)


def apply_spec(scene: SceneCode, ops: Sequence[EditOp], spec: EditSpec | None = None,
               bank: MeshBank | None = None) -> SceneCode:
    """:func:`~sdn3d.editing.apply.apply_edits`, naming the failing op of ``spec`` in the error."""
    try:
        return apply_edits(scene, ops, bank)
    except EditError as exc:
        # Find the first failing op (only on this error path: applying prefixes costs a few renders).
        for k in range(len(ops)):
            try:
                apply_edits(scene, ops[:k + 1], bank)
            except EditError:
                name = spec.ops[k].describe() if spec is not None and spec.ops else f"op {k}"
                raise EditError(f"{name}: {exc}") from None
        raise
