"""The browser editor's state: the models (one :class:`~sdn3d.editing.session.EditSession`) and the browser sessions.

A *browser session* is one opened image: an unguessable id (``secrets.token_urlsafe``), its own directory
``<output_dir>/sessions/<id>/`` (the uploaded file, ``spec.yaml``, and what is downloaded: ``edited.png``,
``edit.json``, ``edited_scene.glb``, ``command.txt``), and its current spec and picture. Nothing the browser sends is
a path: it sends image bytes, a frame's index in the list the server made, ids, numbers and colour names. Every
file is written atomically (:mod:`sdn3d.io`) and only inside the session's directory.

Every state is a spec. The browser sends the whole state, ``{objects: [{box, class}], ops: [{op: ...}]}`` (pixels of
the input image, as ``sdn3d-edit`` reads them); :meth:`Editor.edit` writes it as YAML, reads that YAML back with
the edit spec's own parser, de-renders once per image and set of boxes (cached by the
:class:`~sdn3d.editing.session.EditSession`) and draws the edit. The YAML and the ``sdn3d-edit`` command line
(:meth:`Editor.command`: the same checkpoints and settings, this input, this spec) reproduce the picture bit for bit.
A state the library refuses (no such object, a target outside the frame, ...) changes nothing and its message
goes back to the browser.
"""

from __future__ import annotations

import math
import os
import re
import secrets
import shlex
import shutil
import threading
import time
from collections import OrderedDict
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from sdn3d.editing.frame import input_intrinsics
from sdn3d.editing.session import BoxRefusedError, EditInput, EditResult, EditSession, to_uint8
from sdn3d.editing.spec import MAX_BOX_OBJECTS, EditSpec, parse_edit_spec
from sdn3d.errors import UserInputError
from sdn3d.io import write_bytes_atomic, write_json_atomic, write_png_atomic, write_text_atomic, yaml_loader
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.proposals import Proposals
from sdn3d.scene.code import SceneCode
from sdn3d.scene.listing import list_objects
from sdn3d.textural.code_bank import NAMED_COLORS

__all__ = ["AppError", "AppLimits", "BrowserSession", "Editor", "IMAGE_TYPES", "DOWNLOADS", "spec_text",
           "image_type", "scene_objects", "encode_png", "palette"]

#: Image types accepted for upload: their leading bytes -> the stored file's suffix.
IMAGE_TYPES = {b"\x89PNG\r\n\x1a\n": ".png", b"\xff\xd8\xff": ".jpg"}
#: What a browser may download from its session, and each file's media type.
DOWNLOADS = {"edited.png": "image/png", "edit.json": "application/json", "edited_scene.glb": "model/gltf-binary",
             "spec.yaml": "application/yaml", "command.txt": "text/plain"}
_SID_CHARS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_")
#: Longest string value of an op the browser may send (a colour name; an edit spec quotes at most this much).
_MAX_TEXT = 40


class AppError(UserInputError):
    """A request the editor refuses; ``status`` is its HTTP status (4xx) and the message says why."""

    def __init__(self, message: str, status: int = 422, extra: dict | None = None) -> None:
        super().__init__(message)
        self.status = int(status)
        self.extra = dict(extra or {})  # more fields of the JSON answer (e.g. which boxes were refused)


@dataclass(frozen=True)
class AppLimits:
    """What one request may ask of the server (``conf/app.yaml``).

    Attributes:
        max_upload_bytes: the largest uploaded image file.
        max_upload_pixels: the most pixels an uploaded image may declare (read from its header before decoding;
            the project's image reader refuses more than 100 MP in any case).
        max_edit_pixels: an upload with more pixels is scaled down to this many (its aspect ratio kept) when it is
            opened, and that copy is the session's input (its spec and command line refer to it): every
            interaction's work grows with the input's pixels (a click's box: 1 s at 0.47 MP, 6 s at 1 MP, 41 s at
            4 MP on 2 shared CPU cores).
        max_request_bytes: the largest JSON request.
        max_sessions: browser sessions kept; opening one more closes the least recently used if it was idle for
            ``session_idle_s`` seconds, else the new one is refused (503): requests never close a session in use.
        max_ops: the most operations a spec may hold (``sdn3d-edit``'s ``max_ops``).
        session_idle_s: seconds without a request after which a session may be closed to make room.
    """

    max_upload_bytes: int = 20_000_000
    max_upload_pixels: int = 25_000_000
    max_edit_pixels: int = 1_000_000
    max_request_bytes: int = 65_536
    max_sessions: int = 8
    max_ops: int = 256
    session_idle_s: int = 1800

    def __post_init__(self) -> None:
        for name in ("max_upload_bytes", "max_upload_pixels", "max_edit_pixels", "max_request_bytes", "max_sessions",
                     "max_ops", "session_idle_s"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise UserInputError(f"{name} must be a positive integer, got {value!r}")


@dataclass
class BrowserSession:
    """One opened image (module doc)."""

    sid: str
    directory: Path
    input: EditInput
    input_args: list[str]
    lock: threading.Lock = field(default_factory=threading.Lock)
    state: dict = field(default_factory=lambda: {"objects": [], "ops": []})
    spec_yaml: str = ""
    result: EditResult | None = None
    scene: SceneCode | None = None
    picture: np.ndarray | None = None
    png: bytes = b""
    input_png: bytes = b""
    version: int = 0
    warnings: list[str] = field(default_factory=list)
    written: dict[str, int] = field(default_factory=dict)  # download name -> the version it was written for
    used: float = field(default_factory=time.monotonic)  # the last request's time (time.monotonic)
    input_note: str = ""  # how the upload was changed to become the input (scaled down: max_edit_pixels)
    display_name: str = ""  # the uploaded file's own name, as the browser gave it (shown only; never a path)


def image_type(data: bytes) -> str:
    """The suffix of an accepted image (:data:`IMAGE_TYPES`, by content, not by name).

    Raises:
        AppError (415): anything else.
    """
    for magic, suffix in IMAGE_TYPES.items():
        if data.startswith(magic):
            return suffix
    raise AppError("only PNG and JPEG images are accepted (the file's first bytes are neither)", 415)


def encode_png(picture: np.ndarray, level: int = 1) -> bytes:
    """``(H, W, 3)`` uint8 as PNG bytes, fast (zlib ``level``; the pixels are exact at every level)."""
    import cv2

    ok, data = cv2.imencode(".png", np.ascontiguousarray(picture[:, :, ::-1]), [cv2.IMWRITE_PNG_COMPRESSION, level])
    if not ok:
        raise RuntimeError("PNG encoding failed")
    return data.tobytes()


def _yaml_value(value: Any) -> str:
    """One value of a spec written as YAML flow (JSON-compatible: strings quoted, floats by ``repr``, which
    YAML reads back to the same float)."""
    import json

    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    return "[" + ", ".join(_yaml_value(v) for v in value) + "]"


def _flow(mapping: Mapping[str, Any]) -> str:
    return "{" + ", ".join(f"{k}: {_yaml_value(v)}" for k, v in mapping.items()) + "}"


def spec_text(objects: Sequence[Mapping[str, Any]], ops: Sequence[Mapping[str, Any]]) -> str:
    """The edit spec (YAML, one op a line) of a state: ``{objects: [...], ops: [...]}`` (``objects`` only when
    there are some; ``ops: []`` for none)."""
    lines = ["# sdn3d-app edit spec: pixels of the input image (sdn3d-edit edits=<this file>)"]
    if objects:
        lines.append("objects:")
        lines += [f"  - {_flow(o)}" for o in objects]
    lines.append("ops:" if ops else "ops: []")
    lines += [f"  - {_flow(o)}" for o in ops]
    return "\n".join(lines) + "\n"


def _clean_value(value: Any, what: str, depth: int = 0) -> Any:
    """A value of an op as the browser may send it: a finite number, a bool, a short string, or a list of at most
    eight numbers (anything else, a list nested deeper than two levels included, is refused naming the field)."""
    if isinstance(value, bool) or (isinstance(value, int) and abs(value) < 2**53):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise AppError(f"{what} must be finite, got {value!r}")
        return value
    if isinstance(value, str):
        if len(value) > _MAX_TEXT:
            raise AppError(f"{what} is {len(value)} characters long, more than {_MAX_TEXT}")
        return value
    if isinstance(value, list) and len(value) <= 8 and depth < 2:
        return [_clean_value(v, f"{what}[{i}]", depth + 1) for i, v in enumerate(value)]
    raise AppError(f"{what} must be a number, true/false, a short text or a short list, got {type(value).__name__}")


def _clean_state(payload: Any, max_ops: int) -> dict:
    """``{objects, ops}`` of a request, each a list of flat mappings (:func:`_clean_value`); the edit spec's parser
    checks the rest."""
    if not isinstance(payload, dict) or set(payload) - {"objects", "ops"}:
        raise AppError("send {objects: [...], ops: [...]} (a JSON object with those keys only)")
    out = {}
    for key, limit in (("objects", MAX_BOX_OBJECTS), ("ops", max_ops)):
        items = payload.get(key) or []
        if not isinstance(items, list):
            raise AppError(f"{key} must be a list, got {type(items).__name__}")
        if len(items) > limit:
            raise AppError(f"{len(items)} {key}, more than {limit}")
        clean = []
        for i, item in enumerate(items):
            if not isinstance(item, dict) or len(item) > 8:
                raise AppError(f"{key}[{i}] must be a mapping of at most 8 fields")
            row = {}
            for name, value in item.items():
                if not isinstance(name, str) or not name.isidentifier() or len(name) > 16:
                    raise AppError(f"{key}[{i}]: field names are short words, got {str(name)[:20]!r}")
                row[name] = _clean_value(value, f"{key}[{i}].{name}")
            clean.append(row)
        out[key] = clean
    return out


def scene_objects(scene: SceneCode, inp: EditInput) -> list[dict]:
    """The scene's objects as the page draws them: :func:`~sdn3d.scene.listing.list_objects`' rows (input pixels)
    with the 3D box at full precision (``center`` of the box in the camera frame, metres; ``dims`` ``(l, h, w)``;
    ``ry`` radians) for the outlines the page projects itself while dragging."""
    rows = list_objects(scene, inp.input_size, inp.frame)
    table = scene.objects
    for i, row in enumerate(rows):
        geometry = bool(table.template_id[i] >= 0)
        row["geometry"] = geometry
        row["thing_class"] = int(table.instance_id[i]) // INSTANCE_DIVISOR
        if geometry:
            row["center"] = [float(v) for v in table.center[i].double()]
            row["dims"] = [float(v) for v in table.dims[i].double()]
            row["ry"] = float(table.ry[i])
    return rows


class Editor:
    """The browser sessions of one server, over one :class:`~sdn3d.editing.session.EditSession`.

    Args:
        session: the models and the de-render cache.
        output_dir: where the sessions' directories go (``<output_dir>/sessions/<id>``); nothing is written elsewhere.
        open_input: the ``input.*`` values (``{'image': <file>[, 'intrinsics': {fx, fy, cx, cy}]}`` or
            ``{'frame': <key>}``) -> the :class:`~sdn3d.editing.session.EditInput` ``sdn3d-edit`` would make of them
            (same camera rules, same errors; :func:`sdn3d.cli.edit.open_input`).
        frames: the keys of the frames a browser may pick (a dataset given at start), by index.
        command: the ``sdn3d-edit`` arguments every reproduction takes (checkpoints, settings), in order.
        record: extra fields of edit.json (the checkpoints, the config).
        limits: :class:`AppLimits`.
        workdir: the directory the command line runs from (its relative paths are relative to it).
    """

    def __init__(self, session: EditSession, output_dir: str | os.PathLike,
                 open_input: Callable[[dict[str, Any], str], EditInput], frames: Sequence[str] = (),
                 command: Sequence[str] = (), record: Mapping[str, Any] | None = None,
                 limits: AppLimits | None = None, workdir: str | os.PathLike | None = None) -> None:
        self.session = session
        self.output_dir = Path(output_dir).expanduser().resolve()
        self.sessions_dir = self.output_dir / "sessions"
        self.sessions_dir.mkdir(parents=True, exist_ok=True)
        self.open_input = open_input
        self.frames = list(frames)
        self.command_args = list(command)
        self.record = dict(record or {})
        self.limits = limits or AppLimits()
        self.workdir = Path(workdir or Path.cwd()).resolve()
        self._sessions: OrderedDict[str, BrowserSession] = OrderedDict()
        self._lock = threading.Lock()

    # -- sessions ---------------------------------------------------------------------------------------------

    def get(self, sid: str) -> BrowserSession:
        """The browser session ``sid``.

        Raises:
            AppError (404): no such session (a malformed id included: it never reaches the file system).
        """
        if not isinstance(sid, str) or not 16 <= len(sid) <= 64 or not set(sid) <= _SID_CHARS:
            raise AppError("no such session", 404)
        with self._lock:
            found = self._sessions.get(sid)
            if found is None:
                raise AppError("no such session (closed, or the server was restarted): open the image again", 404)
            self._sessions.move_to_end(sid)
            found.used = time.monotonic()
            return found

    def _make_room(self) -> None:
        """Close the least recently used sessions idle for ``session_idle_s`` until one more fits (caller holds
        ``_lock``).

        Raises:
            AppError (503): every session was used recently: none is closed for a new one.
        """
        while len(self._sessions) >= self.limits.max_sessions:
            oldest = next(iter(self._sessions.values()))
            idle = time.monotonic() - oldest.used
            if idle < self.limits.session_idle_s:
                raise AppError(f"the server holds {len(self._sessions)} open images (max_sessions), the least recently "
                               f"used {idle:.0f} s ago, less than session_idle_s={self.limits.session_idle_s}: "
                               "close one (or restart sdn3d-app with a larger max_sessions)", 503)
            self._close(self._sessions.popitem(last=False)[1])

    def _new(self, make_input: Callable[[Path], tuple[EditInput, list[str]]]) -> BrowserSession:
        with self._lock:
            self._make_room()  # before any work: a refused open costs no de-render
        sid = secrets.token_urlsafe(16)
        directory = self.sessions_dir / sid
        directory.mkdir()
        try:
            inp, args = make_input(directory)
        except BaseException:
            shutil.rmtree(directory, ignore_errors=True)
            raise
        png = encode_png(inp.picture)
        found = BrowserSession(sid, directory, inp, args, spec_yaml=spec_text([], []), picture=inp.picture, png=png,
                               input_png=png)
        write_text_atomic(directory / "spec.yaml", found.spec_yaml)
        with self._lock:
            try:
                self._make_room()
            except AppError:
                self._close(found)
                raise
            self._sessions[sid] = found
        return found

    def _close(self, found: BrowserSession) -> None:
        self.session.forget(found.sid)
        if found.directory.parent == self.sessions_dir:  # only a session directory of this editor is removed
            shutil.rmtree(found.directory, ignore_errors=True)

    def close(self, sid: str) -> None:
        """Close a session: its scenes are forgotten and its directory removed."""
        found = self.get(sid)
        with self._lock:
            self._sessions.pop(sid, None)
        self._close(found)

    def open_upload(self, data: bytes, intrinsics: Mapping[str, float] | None = None,
                    name: str | None = None) -> BrowserSession:
        """A session for an uploaded image file's bytes (``intrinsics``: fx, fy, cx, cy in its pixels, for an image
        without Virtual KITTI's aspect ratio; ``name``: the file's own name, shown by the page, never used as a
        path: the upload is stored as ``input.png`` / ``input.jpg`` in the session's directory).

        Raises:
            AppError: 413 too many bytes or pixels, 415 not PNG / JPEG, 422 the image or its camera refused (the
                message ``sdn3d-edit`` gives).
        """
        from sdn3d.data.errors import DataFormatError
        from sdn3d.data.imageio import image_size

        if len(data) > self.limits.max_upload_bytes:
            raise AppError(f"the image is {len(data)} bytes, more than the {self.limits.max_upload_bytes} accepted "
                           "(max_upload_bytes)", 413)
        suffix = image_type(data)
        values = {}
        if intrinsics:
            values = {k: _clean_value(intrinsics[k], f"intrinsics.{k}") for k in ("fx", "fy", "cx", "cy")
                      if k in intrinsics}
            if len(values) != 4 or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                           for v in values.values()):
                raise AppError("intrinsics: give all of fx, fy, cx, cy as numbers (pixels of the image)")
        notes = []

        def make(directory: Path) -> tuple[EditInput, list[str]]:
            path = write_bytes_atomic(directory / f"input{suffix}", data)
            try:
                width, height = image_size(path)
            except DataFormatError as exc:
                raise AppError(f"the image cannot be read: {str(exc).removeprefix(f'{path}: ')}", 422) from None
            if width * height > self.limits.max_upload_pixels:
                raise AppError(f"the image is {width}x{height} = {width * height / 1e6:.1f} MP, more than the "
                               f"{self.limits.max_upload_pixels / 1e6:g} MP accepted (max_upload_pixels)", 413)
            camera = dict(values)
            if width * height > self.limits.max_edit_pixels:
                path, camera, note = self._scaled_input(path, width, height, camera)
                notes.append(note)
            given: dict[str, Any] = {"image": str(path)}
            args = [f"input.image={path}"]  # the command line's input (the page shows it)
            if camera:
                given["intrinsics"] = {k: float(v) for k, v in camera.items()}
                args.append("input.intrinsics={" + ",".join(f"{k}:{float(v)!r}" for k, v in camera.items()) + "}")
            return self._input(given, directory.name), args

        found = self._new(make)
        found.input_note = " ".join(notes)
        found.display_name = display_name(name)
        return found

    def _scaled_input(self, path: Path, width: int, height: int, camera: dict) -> tuple[Path, dict, str]:
        """An upload over ``max_edit_pixels`` scaled down to at most that many pixels (aspect ratio kept, area
        resampling) as ``input.png`` beside it (the upload removed), with ``camera`` (fx, fy, cx, cy of the upload)
        following the resize; and the note the page shows."""
        import cv2

        from sdn3d.data.errors import DataFormatError
        from sdn3d.data.imageio import read_rgb

        scale = math.sqrt(self.limits.max_edit_pixels / (width * height))
        size = (max(1, int(width * scale)), max(1, int(height * scale)))
        try:
            rgb = read_rgb(path)
        except DataFormatError as exc:
            raise AppError(f"the image cannot be read: {str(exc).removeprefix(f'{path}: ')}", 422) from None
        scaled = write_png_atomic(path.with_name("input.png"), cv2.resize(rgb, size, interpolation=cv2.INTER_AREA))
        if scaled != path:
            path.unlink()
        sx, sy = size[0] / width, size[1] / height
        if camera:  # Intrinsics.resized: pixel centres at integer coordinates
            camera = {"fx": camera["fx"] * sx, "fy": camera["fy"] * sy, "cx": (camera["cx"] + 0.5) * sx - 0.5,
                      "cy": (camera["cy"] + 0.5) * sy - 0.5}
        note = (f"the {width}x{height} upload was scaled to {size[0]}x{size[1]} for editing (max_edit_pixels="
                f"{self.limits.max_edit_pixels}: each interaction's work grows with the pixels); the spec, the "
                "command line and the downloads refer to the scaled copy")
        return scaled, camera, note

    def open_frame(self, index: Any) -> BrowserSession:
        """A session for the dataset frame ``frames[index]``.

        Raises:
            AppError (404): no dataset, or no such frame.
        """
        if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < len(self.frames):
            raise AppError(f"frame must be an index in [0, {len(self.frames)}) of the frames the server lists, got "
                           f"{str(index)[:20]!r}", 404 if self.frames else 400)
        args = [f"input.frame={self.frames[index]}"]
        return self._new(lambda directory: (self._input({"frame": self.frames[index]}, directory.name), args))

    def _input(self, given: dict[str, Any], sid: str) -> EditInput:
        try:
            return self.open_input(given, sid)
        except AppError:
            raise
        except UserInputError as exc:  # the camera rules, an unreadable image: sdn3d-edit's own message
            raise AppError(page_words(str(exc)), 422) from None

    # -- edits ------------------------------------------------------------------------------------------------

    def parse(self, state: dict) -> EditSpec | None:
        """The edit spec of a clean state, read back from its YAML by the edit spec's parser (None: empty)."""
        import yaml

        if not state["objects"] and not state["ops"]:
            return None
        text = spec_text(state["objects"], state["ops"])
        return parse_edit_spec(yaml.load(text, Loader=yaml_loader()), "spec", self.limits.max_ops)  # noqa: S506

    def edit(self, sid: str, payload: Any) -> BrowserSession:
        """Make ``payload`` (``{objects, ops}``) the session's state: de-render (once per set of boxes), edit, draw.

        Raises:
            AppError (404 no such session; 422 a state the edit spec or the library refuses: nothing changes).
        """
        found = self.get(sid)
        state = _clean_state(payload, self.limits.max_ops)
        with found.lock:
            try:
                spec = self.parse(state)
                # An empty state (Reset, undo to the start) is the input's own scene: none with proposals=boxes
                boxes_only = self.session.settings.proposals is Proposals.BOXES
                derendered = self.session.derender(found.input, spec) if spec is not None or not boxes_only else None
                result = self.session.edit(derendered, spec) if spec is not None and len(spec) else None
            except BoxRefusedError as exc:  # the page offers to add them anyway (force: true)
                raise AppError(str(exc), 422, {"refused_objects": exc.objects}) from None
            except UserInputError as exc:
                raise AppError(str(exc), 422) from None
            picture = result.edited if result is not None else found.input.picture
            found.state, found.result, found.picture = state, result, picture
            found.scene = (result.edited_scene if result is not None else
                           derendered.scene if derendered is not None else None)
            found.warnings = (derendered.warnings if derendered is not None else []) + (
                result.warnings if result is not None else [])
            found.spec_yaml = spec_text(state["objects"], state["ops"])
            found.png = encode_png(picture)
            found.version += 1
            write_text_atomic(found.directory / "spec.yaml", found.spec_yaml)
            return found

    def scene(self, sid: str) -> BrowserSession:
        """The session with its scene de-rendered (the first look at an image: nothing edited yet)."""
        found = self.get(sid)
        with found.lock:
            # proposals=boxes: no object until a box is drawn (de-rendering without one is refused)
            boxes_only = self.session.settings.proposals is Proposals.BOXES
            if found.scene is None and (found.state["objects"] or not boxes_only):
                try:
                    spec = self.parse(found.state)
                    found.scene = self.session.derender(found.input, spec).scene
                except UserInputError as exc:
                    raise AppError(str(exc), 422) from None
            return found

    def box_at(self, sid: str, payload: Any) -> dict:
        """The box a click implies (:func:`sdn3d.box_masks.box_at_point`): ``payload`` ``{"u": x, "v": y}`` in the
        input's pixels -> ``{"box": [x0, y0, x1, y1] half-open input pixels, "refused": why no vehicle is there
        (:func:`sdn3d.box_masks.no_vehicle`: GrabCut found nothing, or the road plane says no car that size stands
        there) or None}``, for the page to show and add as an object (a refused one only when the user says so).

        Raises:
            AppError (404 no such session; 400 not such a payload; 422 a point outside the input).
        """
        import math

        from sdn3d.box_masks import click_box, no_vehicle
        from sdn3d.editing.frame import input_intrinsics
        from sdn3d.geometric.fit import FitSettings

        found = self.get(sid)
        if not isinstance(payload, dict) or set(payload) != {"u", "v"}:
            raise AppError('send {"u": <x>, "v": <y>} in the input\'s pixels', 400)
        u, v = payload["u"], payload["v"]
        if not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in (u, v)):
            raise AppError("u and v must be finite numbers", 400)
        inp = found.input
        width, height = inp.input_size
        if not (0 <= u < width and 0 <= v < height):
            raise AppError(f"the point ({u:.0f}, {v:.0f}) is outside the {width}x{height} input", 422)
        camera = input_intrinsics(inp.intrinsics, inp.frame)
        road = (self.session.settings.box_fit or FitSettings()).camera_height  # the road the box fit assumes
        with found.lock:
            box, found = click_box(inp.picture, (float(u), float(v)), camera.fx, camera.fy, camera.cy,
                                   camera_height=road)
        box = [int(round(float(x))) for x in box]
        why = no_vehicle(box, camera.fx, camera.fy, camera.cy, (width, height), camera_height=road, found=found)
        return {"box": box, "refused": None if why is None else f"no vehicle at ({u:.0f}, {v:.0f}): {why}"}

    # -- what the page shows and downloads ----------------------------------------------------------------------

    def command(self, found: BrowserSession) -> str:
        """The ``sdn3d-edit`` command line that reproduces the session's picture bit for bit."""
        args = [*found.input_args, f"edits={found.directory / 'spec.yaml'}", *self.command_args,
                f"output_dir={found.directory / 'sdn3d-edit'}"]
        return f"cd {shlex.quote(str(self.workdir))} && sdn3d-edit " + " ".join(shlex.quote(a) for a in args)

    def view(self, found: BrowserSession) -> dict:
        """What the page needs after an open or an edit (JSON)."""
        inp = found.input
        camera = input_intrinsics(inp.intrinsics, inp.frame)
        times = found.result.times if found.result is not None else {}
        return {"sid": found.sid, "version": found.version,
                "input": {"name": found.display_name or Path(inp.name).name, "file": Path(inp.name).name,
                          "width": inp.input_size[0], "height": inp.input_size[1]},
                "working_size": [inp.intrinsics.width, inp.intrinsics.height],
                "camera": {"fx": camera.fx, "fy": camera.fy, "cx": camera.cx, "cy": camera.cy},
                "objects": scene_objects(found.scene, inp) if found.scene is not None else [],
                "classes": [{"id": c.id, "name": c.name, "color": list(c.color), "thing": c.has_instances}
                            for c in (found.scene.class_list if found.scene is not None else ())],
                "present_classes": (found.scene.semantic.unique().tolist() if found.scene is not None else []),
                "frame": inp.frame.to_dict(),
                "state": found.state, "spec": found.spec_yaml, "command": self.command(found),
                "warnings": [found.input_note] * bool(found.input_note) + found.warnings,
                "labels_note": self.labels_note(),
                "timings_ms": {k: round(v, 1) for k, v in times.items()}}

    def labels_note(self) -> str:
        """Where the labels overlay (the semantic map) comes from, when it cannot be trusted: no semantic branch
        (then it holds the box objects alone), one whose recorded validation quality is low
        (:func:`sdn3d.runs.quality_warnings`) or not recorded; "" otherwise."""
        if not hasattr(self, "_labels_note"):
            import json

            from sdn3d.runs import quality_warnings, semantic_summary

            info = (self.record.get("checkpoints") or {}).get("semantic")
            if info is None:
                note = ("labels: no semantic branch is loaded; the map holds the objects named by a box on the "
                        "background class only")
            else:
                path, metrics = semantic_summary(info), None
                try:
                    metrics = json.loads(path.read_text(encoding="utf-8")).get("metrics") if path else None
                except (OSError, UnicodeDecodeError, ValueError, AttributeError):
                    metrics = None
                weak = quality_warnings(metrics, None, str(path) if path else "") if metrics else []
                note = (f"labels: from a weak semantic branch ({weak[0]})" if weak else
                        "" if metrics else "labels: from a semantic branch whose validation quality is not recorded "
                        f"(no summary.json beside {info.get('path')}): they may be wrong")
            self._labels_note = note
        return self._labels_note

    def labels_png(self, sid: str) -> bytes:
        """The current scene's semantic map (working size) in the class colours, as PNG."""
        from sdn3d.visualize import colorize_labels

        found = self.scene(sid)
        if found.scene is None:
            raise AppError("no scene yet: draw a box around an object first (proposals=boxes)", 409)
        return encode_png(to_uint8(colorize_labels(found.scene.semantic[None].cpu(), found.scene.class_list)[0]))

    def download(self, sid: str, name: str) -> Path:
        """The file ``name`` (:data:`DOWNLOADS`) of the session's current state, written (atomically, in its
        directory) if this state has not been written yet.

        Raises:
            AppError (404): not a download name, or no such session.
        """
        if name not in DOWNLOADS:
            raise AppError(f"no download {name[:40]!r}; the downloads are {sorted(DOWNLOADS)}", 404)
        found = self.scene(sid)
        if found.scene is None and name == "edited_scene.glb":
            raise AppError("no scene yet: draw a box around an object first (proposals=boxes)", 409)
        path = found.directory / name
        with found.lock:
            if found.written.get(name) == found.version and path.is_file():
                return path
            if name == "edited.png":
                write_png_atomic(path, found.picture)
            elif name == "spec.yaml":
                write_text_atomic(path, found.spec_yaml)
            elif name == "command.txt":
                write_text_atomic(path, self.command(found) + "\n")
            elif name == "edited_scene.glb":
                from sdn3d.export import export_gltf

                export_gltf(found.scene, path)
            else:
                write_json_atomic(path, self.edit_record(found))
            found.written[name] = found.version
        return path

    def edit_record(self, found: BrowserSession) -> dict:
        """edit.json of the current state: what ``sdn3d-edit`` writes (ops, objects, timings, photo, ...) with the
        command line and the spec that reproduce it."""
        head = {"input": found.input.name, "edits": str(found.directory / "spec.yaml"), "command": self.command(found),
                "written_by": "sdn3d-app", "written_at": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        if found.result is None:
            return head | {"ops": [], "warnings": found.warnings, **self.record}
        body = found.result.record(self.session.settings.appearance)
        return head | body | self.record


def display_name(name: str | None) -> str:
    """An uploaded file's own name as the page may show it: its last path part, printable characters only, at most
    80 ("" when none is left)."""
    if not name:
        return ""
    base = str(name).replace("\\", "/").rsplit("/", 1)[-1]
    return "".join(c for c in base if c.isprintable())[:80].strip()


_UNKNOWN_CAMERA = re.compile(r"input\.image is (\d+)x(\d+), not Virtual KITTI's (\d+)x(\d+)")


def page_words(message: str) -> str:
    """``sdn3d-edit``'s message about an input, in the page's own words where the page has its own control (the
    camera of an image without Virtual KITTI's aspect ratio: the page's **camera** fields, not ``input.*``)."""
    found = _UNKNOWN_CAMERA.search(message)
    if found is None:
        return message
    w, h, vw, vh = found.groups()
    return (f"this image is {w}x{h}, not Virtual KITTI's {vw}x{vh} (or that aspect ratio), so its camera is unknown: "
            f"open 'camera' in the toolbar, give fx, fy, cx, cy (pixels of this {w}x{h} image) and open the image "
            "again")


def palette() -> list[dict]:
    """The named colours a car may be repainted with (``recolor: {color: <name>}``), sRGB 0-255 for the swatches."""
    return [{"name": n, "rgb": [round(255 * c) for c in rgb]} for n, rgb in NAMED_COLORS.items()]
