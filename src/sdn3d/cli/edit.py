"""``sdn3d-edit``: de-render an image (or a dataset frame), edit it in 3D, render the result.

Configuration ``conf/edit.yaml`` (Hydra overrides as arguments, e.g. ``input.image=x.png``).
Everything is checked before anything is written: the edit spec's syntax and numbers first
(before loading networks), then against the de-rendered scene (objects exist, targets inside the
frame, 3D edits on objects with geometry). The output directory is then written all at once (staged beside it;
an existing one is replaced only if it holds nothing but the files an earlier run's ``edit.json`` lists under
``outputs`` and none of this run's inputs, :func:`_output_rules`):

    edited.png                                              the result (``appearance``, below)
    maps/photo_source.png                                   appearance=photo: where each pixel came from (dark
                                                            grey input, green photo, blue mirror, red fallback,
                                                            yellow inpainted, violet repainted, grey shadow)
    generated.png                                           the generator's whole edited picture (working size;
                                                            appearance=generator, fill=generator or diagnostics)
    maps/edit_region.png                                    the pixels taken from the generator (compose=edited)
    scene.json/.npz edited_scene.json/.npz                  SceneCode (sdn3d.scene.code)
    edit.json                                               resolved ops, objects, checkpoints, timings,
                                                            input_transform, warnings
    with diagnostics=true also (they cost a second generator pass and the glTF exporter's import):
    source.png reconstruction.png overview.png              images (working size)
    maps/{source,edited}_{label,instance,normal,pose,depth}.png
    scene.glb edited_scene.glb                              3D scenes (sdn3d.export)

The camera is never guessed silently: an image file needs ``input.intrinsics`` or ``input.camera`` (a
Cityscapes ``camera.json``) unless it has Virtual KITTI's aspect ratio. It is scaled to the working size
keeping its aspect ratio, the excess cropped centrally (``input_transform`` in ``edit.json``); the edit
spec's pixels are the input image's (``frame_size`` overrides). Warnings (stderr and ``edit.json``) say when
the semantic branch's recorded validation quality is low or its proposals cover most of the frame.

``appearance=photo`` (default): ``edited.png`` has the input's resolution; each edited car is drawn with the
input's own pixels carried through its fitted 3D shape, its hidden side from the mirror image or its body colour,
re-shaded for its new pose, the road it left inpainted (``photo.*``, :mod:`sdn3d.editing.photo`); ``edit.json``
``photo`` records the light, per object the share of pixels from the photo, the mirror and the fallback, and
warnings. ``appearance=generator`` is the paper's: the textural generator draws the edit, composed by ``compose``.

``compose=edited`` (default of the generator appearance): ``edited.png`` has the input's resolution; only the
edit region (the edited objects' source and target footprints and every pixel whose generator inputs changed,
dilated by
``compose_dilate_px``) comes from the generator, upsampled through the inverse of ``input_transform`` and
blended with a mask feathered over ``compose_feather_px``; every other pixel is the input's, bit for bit
(:mod:`sdn3d.editing.compose`). ``compose=full``: ``edited.png`` is the generator's whole picture at the
working size (the paper's protocol). ``edit.json`` records the mode, the region and the compose time.

``list=true`` (or an empty edit spec) de-renders and edits nothing: it prints the found objects (id,
class, box, projected centre, distance, yaw, template; boxes and centres in the input image's pixels)
and writes only ``objects.json``, ``objects.png`` (the input image with the boxes) and ``edit.json``.

``run=<dir>`` takes the branches' checkpoints from the ``sdn3d-train`` summaries under ``dir`` (a demo
output ``<dir>/runs/<branch>/summary.json``, one run directory, or a training root
``<branch>/<time>/summary.json``): per branch the latest run with status ok, its best checkpoint else
its last. ``checkpoints.<branch>=`` given explicitly wins.

One run writes an ``output_dir`` at a time: a lock file ``.<name>.lock`` beside it names the writer (pid, host,
start time); a second run meanwhile stops with exit 2, and a lock left by a killed run is replaced.

Exit status: 0 done; 2 bad input (message on stderr names the op or the setting; no output).
"""

from __future__ import annotations

import gc
import os

# Before torch loads OpenMP (which reads it once): idle OpenMP threads sleep instead of spinning. With threads=2 on
# the shared 2-core machine one edit with 10 boxes spent 52-111 CPU seconds spinning, against 9 without
# (docs/results/2026-11-28_cpu/session5/cost); a caller's own setting wins.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

# The imports below make about a million objects (torch's most of them) that live as long as the process. The cyclic
# garbage collector, running while they are made, walks them again and again and frees nothing (0.14 CPU s of every
# call). So it pauses for the imports, and what they made then goes straight to the oldest generation (gc.freeze, then
# gc.unfreeze: no collection walks them until a full one), unless the caller keeps objects frozen of its own (they
# stay frozen). Nothing computed changes (issue 40; the measurements: docs/results/2026-11-30_cpu/session26/cost40). A
# caller that had stopped the collector keeps it stopped. (Nothing is left frozen: gc.get_referrers, which Hypothesis
# uses, does not see frozen objects. The program itself freezes them in main(), its process ending with the call.)
_collecting = gc.isenabled()
gc.disable()
try:
    import contextlib
    import dataclasses
    import json
    import sys
    import time
    from collections.abc import Sequence
    from pathlib import Path
    from typing import Any, NoReturn

    import numpy as np
    import torch

    from sdn3d.cli._config import compose_config, print_help_if_asked
    from sdn3d.cli._errors import run_cli
    from sdn3d.editing.appearance import Appearance
    from sdn3d.editing.inputs import camera_for_image, fit_image
    from sdn3d.editing.session import EditInput, EditResult, EditSession, proposals_record, to_uint8
    from sdn3d.editing.settings import appearance_settings, compose_settings, semantic_metrics, session_settings
    from sdn3d.errors import InputError
    from sdn3d.io import OWNER_FILE, TorchFiles, check_output_dir, staged_directory
    from sdn3d.proposals import Proposals
    from sdn3d.runs import BRANCHES, checkpoints_from_run, given_checkpoints, quality_warnings
    from sdn3d.scene.listing import list_objects, objects_table

finally:
    if gc.get_freeze_count() == 0:
        gc.freeze()
        gc.unfreeze()
    if _collecting:
        gc.enable()


__all__ = ["main", "run_edit", "load_input", "open_input", "resolve_checkpoints", "load_models",
           "check_settings", "trust_warnings", "config_record"]

MARKER = "edit.json"
DEFAULT_SIZE = (624, 192)


def _find_record(records: list, frame: Any, entry: Any) -> Any:
    if frame is None:
        if entry is None:
            raise InputError("input.frame is required with data= (or give a benchmark entry to take it from)")
        hits = [r for r in records if (r.world, r.variation, r.frame) == (entry.world, entry.variation,
                                                                         entry.source_frame)]
        what = f"{entry.world}/{entry.variation} frame {entry.source_frame} (benchmark entry source)"
    elif isinstance(frame, int):
        if not 0 <= frame < len(records):
            raise InputError(f"input.frame {frame} is outside the {len(records)} frames of the dataset")
        return records[frame]
    else:
        key = str(frame).strip("/")
        hits = [r for r in records if r.key == key] or [r for r in records if r.key.endswith("/" + key)]
        what = f"input.frame {frame!r}"
    if len(hits) != 1:
        raise InputError(f"{what} matches {len(hits)} frames of the dataset"
                         + (f", e.g. {[r.key for r in hits[:3]]}" if hits else ""))
    return hits[0]


def _given_camera(cfg: Any, width: int, height: int) -> Any:
    """The camera the user gave for an image file: ``input.intrinsics`` (fx, fy, cx, cy in its pixels; optional
    ``camera_height`` and ``pitch``) or ``input.camera`` (a Cityscapes ``camera.json``), else None.

    A pitched camera is returned as its level virtual camera (:meth:`~sdn3d.math3d.camera.CameraPose.
    level_intrinsics`: the pitch folded into ``cy``), the frame the box fit's road plane ``y = camera_height``
    lives in; :func:`_given_pose` is the pose."""
    from sdn3d.math3d.camera import Intrinsics

    given, camera = cfg.input.get("intrinsics"), cfg.input.get("camera")
    if given is not None and camera is not None:
        raise InputError("give input.intrinsics or input.camera, not both")
    pose = _given_pose(cfg)
    if given is not None:
        try:
            values = {k: v for k, v in dict(given).items() if k not in _POSE_KEYS}
            values.setdefault("width", width)
            values.setdefault("height", height)
            intr = Intrinsics(**values)
        except (TypeError, ValueError) as exc:
            raise InputError(f"input.intrinsics: {exc} (give fx, fy, cx, cy in the image's pixels)") from exc
        return pose["pose"].level_intrinsics(intr) if pose else intr
    if camera is not None:
        from sdn3d.data.cityscapes import read_camera
        from sdn3d.errors import UserInputError

        try:
            intrinsic, _ = read_camera(Path(str(camera)).expanduser())
            intr = Intrinsics(intrinsic["fx"], intrinsic["fy"], intrinsic["u0"], intrinsic["v0"], width, height)
        except (UserInputError, ValueError) as exc:
            raise InputError(f"input.camera: {exc}") from exc
        return pose["pose"].level_intrinsics(intr)
    return None


#: Keys of ``input.intrinsics`` that describe the camera's pose, not its calibration (:func:`_given_pose`).
_POSE_KEYS = ("camera_height", "pitch")


def _given_pose(cfg: Any) -> dict | None:
    """How the camera of an image file sits over the road, where the user said: ``{"pose": CameraPose, "height":
    metres or None (not given: box_objects.fit.camera_height stays), "source": setting}`` from ``input.camera``
    (its extrinsic ``z``, ``pitch``, ``roll``) or ``input.intrinsics``' optional ``camera_height`` and ``pitch``;
    None for a dataset frame or when neither says.

    Raises:
        InputError: naming the setting (an unreadable camera file, a height or angle out of range).
    """
    from sdn3d.math3d.camera import DEFAULT_CAMERA_HEIGHT, CameraPose

    node = cfg.get("input") or {}
    if node.get("image") is None:
        return None
    given, camera = node.get("intrinsics"), node.get("camera")
    if camera is not None and given is None:
        from sdn3d.data.cityscapes import camera_pose, read_camera
        from sdn3d.errors import UserInputError

        try:
            _, extrinsic = read_camera(Path(str(camera)).expanduser())
            pose = camera_pose(extrinsic)
        except (UserInputError, ValueError) as exc:
            raise InputError(f"input.camera: {exc}") from exc
        return {"pose": pose, "height": pose.height, "source": "input.camera"}
    if given is None or not any(k in dict(given) for k in _POSE_KEYS):
        return None
    values = dict(given)
    height = values.get("camera_height")
    try:
        pose = CameraPose(height=DEFAULT_CAMERA_HEIGHT if height is None else height, pitch=values.get("pitch", 0.0))
    except ValueError as exc:
        raise InputError(f"input.intrinsics: {str(exc).replace('CameraPose.height', 'camera_height')} "
                         "(camera_height: metres above the road; pitch: radians, positive looking down)") from exc
    return {"pose": pose, "height": None if height is None else pose.height, "source": "input.intrinsics"}


def box_fit_for_input(cfg: Any, fit: Any) -> Any:
    """``fit`` (the box fit's :class:`~sdn3d.geometric.fit.FitSettings` of ``box_objects.fit.*``) with the road plane
    the given camera says (an image file's ``input.camera`` height, or ``input.intrinsics``' ``camera_height``),
    which wins over ``box_objects.fit.camera_height``."""
    pose = _given_pose(cfg)
    return fit if pose is None or pose["height"] is None else dataclasses.replace(fit, camera_height=pose["height"])


def camera_record(cfg: Any) -> dict:
    """``edit.json`` ``camera``: the road plane the box fit used (``camera_height``, metres) and the given camera's
    ``pitch`` (folded into the principal point) and ``roll`` (radians; not corrected, ``roll_ignored`` above
    :data:`~sdn3d.math3d.camera.ROLL_TOLERANCE`), and where they came from."""
    pose = _given_pose(cfg)
    fit = dict((cfg.get("box_objects") or {}).get("fit") or {})
    height_from = "box_objects.fit.camera_height" if "camera_height" in fit else "FitSettings default"
    from sdn3d.math3d.camera import DEFAULT_CAMERA_HEIGHT

    height = float(fit.get("camera_height", DEFAULT_CAMERA_HEIGHT))
    if pose is None:
        return {"camera_height": height, "camera_height_from": height_from, "pitch": 0.0, "roll": 0.0,
                "pose_from": None}
    if pose["height"] is not None:
        height, height_from = pose["height"], pose["source"]
    return {"camera_height": height, "camera_height_from": height_from, "pitch": pose["pose"].pitch,
            "roll": pose["pose"].roll, "roll_ignored": pose["pose"].roll_ignored, "pose_from": pose["source"]}


def _read_input_image(cfg: Any, size: tuple[int, int] | None = None) -> np.ndarray:
    """``input.image`` as ``(H, W, 3)`` uint8 through the project's one image reader
    (:func:`sdn3d.data.imageio.read_rgb`: 16-bit and float images scaled from their own range, unknown modes
    refused; images over ``MAX_IMAGE_PIXELS`` refused before decoding; with the working ``size``, an image whose
    fit to it would be too large, :func:`sdn3d.data.imageio.check_fit`, refused before decoding too).

    Raises:
        InputError: naming ``input.image``: missing, unreadable or of a refused kind.
    """
    from sdn3d.data.errors import DataFormatError
    from sdn3d.data.imageio import check_fit, read_rgb

    path = Path(str(cfg.input.image)).expanduser()
    if not path.is_file():
        raise InputError(f"input.image {str(path)!r} not found")
    try:
        if size is not None:
            check_fit(path, size)
        return read_rgb(path)
    except DataFormatError as exc:
        raise InputError(f"input.image {str(path)!r}: {str(exc).removeprefix(f'{path}: ')}") from exc


def load_input(cfg: Any, entry: Any = None) -> tuple[torch.Tensor, Any, Any, Any]:
    """``(image (3, H, W), intrinsics, record or None, PixelFrame)`` at the working size.

    An image file needs a known camera (:func:`sdn3d.editing.inputs.camera_for_image`) and keeps its aspect
    ratio (:func:`~sdn3d.editing.inputs.fit_image`); a
    dataset frame is resized to the working size as in training. The :class:`~sdn3d.editing.frame.PixelFrame`
    maps the input's pixels (the file, or the frame at its stored size) to the working image's.
    """
    from sdn3d.data.frames import load_frame
    from sdn3d.editing.frame import PixelFrame

    data = cfg.get("data")
    size = cfg.image_size or (data.image_size if data is not None and cfg.input.image is None else DEFAULT_SIZE)
    size = (int(size[0]), int(size[1]))
    if min(size) <= 0:
        raise InputError(f"the working size (image_size, else data.image_size) must be two positive integers "
                         f"[W, H], got {list(size)}")
    if cfg.input.image is not None:
        rgb = _read_input_image(cfg, size)
        height, width = rgb.shape[:2]
        intr, _ = camera_for_image(width, height, _given_camera(cfg, width, height))
        image, intr, frame = fit_image(rgb, intr, size)
        return image, intr, None, frame
    if data is None:
        raise InputError("give input.image=<file> or a dataset (data=<name> and input.frame=<key>)")
    from sdn3d.data.sources import SourceConfig, read_source

    source = SourceConfig.from_mapping(data)
    records = read_source(source)
    if not records:
        raise InputError(f"no frames found under data.root={source.root!r}")
    record = _find_record(records, cfg.input.frame, entry)
    loaded = load_frame(record, size, semantic=False, instances=False)
    stored = (int(record.intrinsics.width), int(record.intrinsics.height))
    return loaded.image, loaded.intrinsics, record, PixelFrame(stored, size)


def open_input(cfg: Any, entry: Any = None, key: str | None = None) -> tuple[EditInput, Any]:
    """``(EditInput, record or None)``: :func:`load_input`'s working image with the input at its own resolution
    (:func:`input_picture`) and, for a dataset frame, its ground truth (for ``proposals`` gt / auto).

    ``key``: the input's name in an :class:`~sdn3d.editing.session.EditSession`'s cache (default: its name).
    """
    image, intrinsics, record, frame = load_input(cfg, entry)
    gt = None
    if record is not None:
        from sdn3d.data.scene_gt import ground_truth

        gt = ground_truth(record, (intrinsics.width, intrinsics.height))
    name = str(cfg.input.image) if record is None else record.key
    return EditInput(image, intrinsics, frame, _input_picture(cfg, record), name, key or name, gt), record


def _map_pictures(maps: Any, classes: Any) -> dict[str, np.ndarray]:
    from sdn3d.visualize import colorize_depth, colorize_ids, colorize_labels, normals_to_rgb, pose_to_rgb

    label = colorize_labels(maps.label[None].cpu(), classes)[0]
    return {"label": to_uint8(label), "instance": colorize_ids(maps.instance), "normal": normals_to_rgb(maps.normal),
            "pose": pose_to_rgb(maps.pose), "depth": colorize_depth(maps.depth[0])}


def _grid(rows: list[list[np.ndarray]]) -> np.ndarray:
    from sdn3d.visualize import hstack_panels

    lines = [hstack_panels(r) for r in rows]
    gap = np.full((4, lines[0].shape[1], 3), 255, np.uint8)
    return np.concatenate([x for line in lines for x in (line, gap)][:-1], 0)


def run_edit(cfg: Any) -> dict:
    """Run the edit described by a composed ``conf/edit.yaml`` config; returns the ``edit.json`` summary.

    Stages: inputs (settings, edit spec, image), networks, de-render, edit, render (one
    :class:`~sdn3d.editing.session.EditSession`, as ``sdn3d-app`` uses), write outputs.

    Raises:
        UserInputError (InputError, EditSpecError, EditError, DataFormatError, ...), FileNotFoundError,
        FileExistsError: bad input (nothing written).
    """
    check_settings(cfg)
    _PROGRESS["on"] = _progress_setting(cfg)
    torch.set_num_threads(int(cfg.threads) if cfg.threads is not None else DEFAULT_THREADS)
    compose = compose_settings(cfg)
    appearance, photo = appearance_settings(cfg)
    out, spec, listing, (inp, record) = _read_inputs(cfg)
    if spec is not None:  # every check that needs no scene, before a model is loaded
        from sdn3d.editing.spec import check_points

        check_points(spec, (inp.intrinsics.width, inp.intrinsics.height), inp.frame)
    # One call, one process: the weights are mapped, not read (the networks page in what they use), and an inference
    # export read for its source record while the run's checkpoints are resolved is not unpickled again for the models.
    files = TorchFiles(mmap=True)
    checkpoints = resolve_checkpoints(cfg, record, files)
    with _stage("loading the models"):
        models, code_bank = load_models(cfg, checkpoints, files)
    settings = session_settings(cfg, checkpoints, compose, appearance, photo)
    settings = dataclasses.replace(settings, box_fit=box_fit_for_input(cfg, settings.box_fit))
    session = EditSession(models, code_bank, settings)
    if spec is not None and spec.objects and settings.proposals is Proposals.BOXES:  # the ids are the boxes': known now
        _check_box_ids(spec, models, inp)
    boxes = f" ({len(spec.objects)} box{'es' if len(spec.objects) != 1 else ''})" if spec and spec.objects else ""
    with _stage(f"de-rendering{boxes}"):
        derendered = session.derender(inp, spec)
    warnings = trust_warnings(cfg, record, checkpoints, derendered.scene) + derendered.warnings
    for line in warnings:
        print(f"sdn3d-edit: warning: {line}", file=sys.stderr)
    if listing:  # list=true, an empty spec or objects without ops: the objects, nothing edited
        return _write_listing(cfg, out, inp, derendered.scene, checkpoints, {"derender_ms": derendered.derender_ms},
                              warnings, derendered.boxes)
    with _stage(f"editing and drawing ({len(spec)} op{'s' if len(spec) != 1 else ''})"):
        result = session.edit(derendered, spec)
    for line in result.warnings:
        print(f"sdn3d-edit: warning: {line}", file=sys.stderr)
    summary = {"input": inp.name, "edits": spec.source, **result.record(appearance)}
    summary["warnings"] = warnings + result.warnings
    summary["checkpoints"] = checkpoints
    summary["config"] = config_record(cfg)
    summary["camera"] = camera_record(cfg)
    with _stage("writing the outputs"):
        _write_outputs(out, bool(cfg.overwrite), result, summary, bool(cfg.diagnostics), _output_rules(cfg))
    return summary


#: torch CPU threads when ``threads`` is not given. 1: on a shared 2-core machine one edit with 3 boxes took
#: 7-30 s with 1 thread and 13-206 s with PyTorch's default (2), pictures identical (docs/EDITING.md, "Threads").
DEFAULT_THREADS = 1


_PROGRESS = {"on": False}


def _progress_setting(cfg: Any) -> bool:
    """``progress``: true, false or auto (the default: when stderr is a terminal; a script reading stderr gets the
    errors alone, one line each)."""
    value = cfg.get("progress", "auto")
    if value == "auto":
        return bool(getattr(sys.stderr, "isatty", lambda: False)())
    if not isinstance(value, bool):
        raise InputError(f"progress must be true, false or auto, got {value!r}")
    return value


@contextlib.contextmanager
def _stage(what: str) -> Any:
    """One progress line on stderr, when ``progress`` is on: ``sdn3d-edit: <what>... 3.1 s`` (the time when the stage
    ends; `failed` if it raises)."""
    if not _PROGRESS["on"]:
        yield
        return
    print(f"sdn3d-edit: {what}...", end="", file=sys.stderr, flush=True)
    start = time.perf_counter()
    try:
        yield
    except BaseException:
        print(" failed", file=sys.stderr, flush=True)
        raise
    print(f" {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)


def _check_box_ids(spec: Any, models: Any, inp: Any) -> None:
    """With ``proposals=boxes`` the objects are the spec's boxes, their ids known from their classes: the ops' ids
    are checked before the de-render (:func:`~sdn3d.editing.spec.check_ids`)."""
    from sdn3d.derender import _class_list_name
    from sdn3d.editing.spec import box_object_ids, box_prompts, check_ids
    from sdn3d.labels import CLASS_LISTS

    classes = CLASS_LISTS[_class_list_name(models, None, None)]
    prompts = box_prompts(spec, (inp.intrinsics.width, inp.intrinsics.height), inp.frame)
    ids = box_object_ids(prompts.class_ids(classes))
    check_ids(spec, ids, ": with proposals=boxes the objects are the spec's boxes, in their order; checked before "
                         "the de-render")


def config_record(cfg: Any) -> dict:
    """The config as edit.json records it (every interpolation resolved; no ``data`` key without a dataset, as
    before the schema gave it one)."""
    from omegaconf import OmegaConf

    record = OmegaConf.to_container(cfg, resolve=True)
    if "data" in record and record["data"] is None:
        del record["data"]
    return record


def _output_rules(cfg: Any) -> dict[str, Any]:
    """:func:`sdn3d.io.check_output_dir`'s rules for ``output_dir``: an earlier edit is replaced only if the directory
    holds nothing but the files its ``edit.json`` lists (``outputs``), and never when it holds one of this run's
    inputs."""
    given = {"input.image": cfg.input.get("image"), "input.camera": cfg.input.get("camera"), "edits": cfg.edits,
             "code_bank": cfg.get("code_bank"), "run": cfg.get("run"),
             **{f"checkpoints.{b}": (cfg.get("checkpoints") or {}).get(b) for b in BRANCHES}}
    return {"listed_in": "outputs", "inputs": {k: str(v) for k, v in given.items() if v is not None}}


def check_settings(cfg: Any) -> None:
    """Refuse ``threads`` below 1, ``pick_radius`` not a positive finite number and ``max_ops`` below 1, naming the
    setting (before anything is loaded; their types are the schema's, sdn3d.cli._schemas)."""
    import math

    threads = cfg.get("threads")
    if threads is not None and threads < 1:
        raise InputError(f"threads must be a positive integer (torch CPU threads) or null for PyTorch's default, "
                         f"got {threads!r}")
    radius = cfg.get("pick_radius")
    if radius is not None and (not math.isfinite(radius) or radius <= 0):
        raise InputError(f"pick_radius must be a positive number of pixels (working size) or null for no limit, "
                         f"got {radius!r}")
    if cfg.max_ops < 1:
        raise InputError(f"max_ops must be a positive integer (the most operations an edit spec may hold), "
                         f"got {cfg.max_ops!r}")


def _is_empty_spec(path: Path) -> bool:
    """Whether the edit spec file holds no ops (empty, ``[]``, ``ops: []``); unreadable files are left to
    :func:`sdn3d.editing.spec.load_edit_spec` to report (YAML through its :func:`~sdn3d.editing.spec.read_yaml`,
    which refuses anchors and aliases before building anything)."""
    from sdn3d.editing.spec import read_yaml
    from sdn3d.errors import UserInputError

    try:
        data = json.loads(path.read_text(encoding="utf-8")) if path.suffix.lower() == ".json" else read_yaml(path)
    except (OSError, UnicodeDecodeError, ValueError, UserInputError):
        return False
    if isinstance(data, dict) and set(data) <= {"ops", "frame_size"}:
        data = data.get("ops")
    return data is None or data == []


def _read_inputs(cfg: Any) -> tuple[Path, Any, bool, tuple[EditInput, Any]]:
    """The checked output directory, the parsed edit spec (None: none given or empty), whether to list the objects
    and edit nothing (``list=true``, no spec, or a spec with objects by box and no ops) and :func:`open_input`'s
    image and record (nothing loaded before the spec's syntax and numbers are checked)."""
    from sdn3d.editing.spec import load_edit_spec

    out = check_output_dir(cfg.output_dir, MARKER, bool(cfg.overwrite), **_output_rules(cfg))
    proposals = _proposals(cfg)
    listing = cfg.list  # true or false (the schema)
    spec = None
    if cfg.edits is None:
        if not listing:
            raise InputError("give an edit spec (edits=<file.yaml or benchmark .json>), or list=true to list "
                             "the objects of the image first")
    elif not _is_empty_spec(Path(str(cfg.edits)).expanduser()):
        spec = load_edit_spec(str(cfg.edits), int(cfg.entry), tuple(cfg.frame_size) if cfg.frame_size else None,
                              cfg.strict, cfg.max_ops)
    if proposals is Proposals.BOXES and (spec is None or not spec.objects):
        raise InputError("proposals=boxes takes the objects from the edit spec's `objects:` list "
                         "({box: [x0, y0, x1, y1], class: Car}, in the input image's pixels); the spec names none")
    inputs = open_input(cfg, spec.entry if spec is not None else None)
    return out, spec, listing or spec is None or len(spec) == 0, inputs


def _needed_branches(cfg: Any, record: Any) -> tuple[str, ...]:
    """The branches an edit cannot do without: the generator, the 3D geometry (unless every object is fitted from a
    box, ``proposals=boxes``), and the semantic branch where no dataset ground truth or box stands in for it (an
    image file, or ``proposals=semantic``)."""
    proposals = _proposals(cfg)
    if proposals is Proposals.BOXES:
        return ("textural",)
    semantic = proposals.needs_semantic_branch(ground_truth=record is not None)
    return ("semantic", "geometric", "textural") if semantic else ("geometric", "textural")


def _proposals(cfg: Any) -> Proposals:
    """``proposals=`` as a :class:`~sdn3d.proposals.Proposals` (InputError naming the values, for another)."""
    return Proposals.parse(cfg.proposals, InputError)


def resolve_checkpoints(cfg: Any, record: Any = None, files: TorchFiles | None = None) -> dict[str, dict | None]:
    """Per branch ``{'path', 'from', ...}`` (None: no checkpoint): ``checkpoints.<branch>`` where given, else
    the ``run`` directory's (:func:`find_run_checkpoints`, its inference exports read through ``files`` where given);
    prints the run's choices on stderr.

    Raises:
        InputError: a bad ``run``, or ``run`` lacks a branch the edit needs (:func:`_needed_branches`).
    """
    if cfg.get("run") is None:
        result = given_checkpoints(cfg.checkpoints)
        _check_needed(cfg, record, result)
        return result
    prog = "sdn3d-app" if "port" in cfg else "sdn3d-edit"  # conf/app.yaml composes this config, with a port
    return checkpoints_from_run(cfg.run, cfg.checkpoints, _needed_branches(cfg, record), prog, "the edit", files)


def _check_needed(cfg: Any, record: Any, given: dict[str, dict | None]) -> None:
    """Without ``run=``, proposals from the semantic branch need its checkpoint; the message says how to give it
    (the generator's is checked when the models load)."""
    if "semantic" not in _needed_branches(cfg, record) or given["semantic"] is not None:
        return
    oracle = (" On a dataset frame, proposals=gt takes the frame's ground-truth masks and semantics instead (an "
              "oracle, for comparison only).") if record is not None else ""
    raise InputError("the semantic branch proposes the objects (proposals=semantic): give checkpoints.semantic=<file> "
                     "(a sdn3d-train checkpoint or inference export), or run=<a training output directory>." + oracle)


def trust_warnings(cfg: Any, record: Any, checkpoints: dict[str, dict | None], scene: Any) -> list[str]:
    """:func:`quality_warnings` for an edit whose proposals come from the semantic branch (none else)."""
    if "semantic" not in _needed_branches(cfg, record):
        return []
    path, metrics = semantic_metrics(checkpoints)
    masks = scene.objects.mask
    coverage = float(masks.any(0).float().mean()) if len(masks) else 0.0
    # What the image is: a frame of the dataset given (its root), or a file; the warning names the real cause by it.
    source = cfg.data.root if record is not None else cfg.input.image
    return quality_warnings(metrics, coverage, str(path) if path is not None else "", input_path=source)


def load_models(cfg: Any, checkpoints: dict[str, dict | None], files: TorchFiles | None = None) -> tuple[Any, Any]:
    """``(Models, CodeBank or None)`` of :func:`resolve_checkpoints`' files and ``code_bank``; ``files``: what reads
    them (:class:`~sdn3d.io.TorchFiles`; None: each is read whole, as the long-running ``sdn3d-app`` does, which should
    not depend on the files staying in place)."""
    from sdn3d.models import Models

    ckpt = {b: None if info is None else info["path"] for b, info in checkpoints.items()}
    if ckpt["textural"] is None:
        raise InputError("checkpoints.textural is required (the generator renders the result; or give "
                         "run=<training output directory>)")
    if cfg.device != "cpu" and not torch.cuda.is_available():
        raise InputError(f"device={cfg.device!r} but CUDA is not available")
    models = Models.from_checkpoints(ckpt["semantic"], ckpt["geometric"], ckpt["textural"], map_location=cfg.device,
                                     crop_size=cfg.geometric.crop_size, margin=cfg.geometric.margin,
                                     semantic_size=cfg.semantic.size, traffic=cfg.geometric.traffic, files=files)
    from sdn3d.textural.code_bank import code_bank_path, load_code_bank

    # sdn3d-train writes <checkpoint>.code_bank.json next to the checkpoint (not to its inference export)
    beside = code_bank_path(checkpoints["textural"].get("checkpoint") or ckpt["textural"])
    if cfg.code_bank is None:
        return models, load_code_bank(beside, "the textural checkpoint's code bank") if beside.is_file() else None
    return models, load_code_bank(str(cfg.code_bank))  # a bad file: UserInputError naming code_bank and it


# -- listing the objects (list=true, or an empty edit spec) ---------------------------------------


def _input_picture(cfg: Any, record: Any) -> np.ndarray:
    """The input image at its own size, ``(H, W, 3)`` uint8 (the dataset frame's file or input.image)."""
    if record is not None:
        from sdn3d.data.records import load_rgb

        return np.ascontiguousarray(load_rgb(record), dtype=np.uint8)
    return _read_input_image(cfg)  # checked by load_input already


def _write_listing(cfg: Any, out: Path, inp: EditInput, scene: Any, checkpoints: dict, times: dict[str, float],
                   warnings: list[str] | None = None, box_records: list[dict] | None = None) -> dict:
    """Print the objects table; write ``objects.json``, ``objects.png`` and ``edit.json`` (staged)."""
    from sdn3d.editing.frame import PixelFrame
    from sdn3d.io import write_json_atomic, write_png_atomic
    from sdn3d.visualize import draw_boxes

    picture, frame = inp.picture, inp.frame
    size = (picture.shape[1], picture.shape[0])
    rows = list_objects(scene, size, frame if frame is not None and tuple(frame.input_size) == size else None)
    boxes = {r["id"]: r for r in box_records or []}
    for row in rows:
        if row["id"] in boxes:
            r = boxes[row["id"]]
            row.update({"given_box": r["input_box"], "mask_from": r["mask"], "pose_from": r["pose"],
                        "fit_iou": r["fit_iou"], "poor_fit": r["poor_fit"]})
    source = inp.name
    frame_text = (f"boxes and centres in input-image pixels ({size[0]}x{size[1]}, pixel centres at integers; "
                  f"working size {scene.image_size[0]}x{scene.image_size[1]})")
    print(f"sdn3d-edit: {len(rows)} object(s) in {source}; {frame_text}")
    print(objects_table(rows))
    print("sdn3d-edit: at/to/from in an edit spec are these pixels (no frame_size needed)")
    title = f"{Path(source).name}: {len(rows)} object(s), id + class; + = projected 3D centre; {size[0]}x{size[1]} px"
    masks = None
    if boxes:  # the masks GrabCut found in the boxes, tinted (at the input's resolution)
        title = (f"{Path(source).name}: {len(rows)} object(s); tint: mask from the box; fit: 3D silhouette IoU; "
                 "+: 3D centre")
        masks = _input_masks(scene, rows, boxes, frame, size)
    labels = [f"{r['id']} {r['class']}" + (f" fit {r['fit_iou']:.2f}" if r.get("fit_iou") is not None else "")
              for r in rows]
    drawn = draw_boxes(picture, [r["box"] for r in rows], labels, title, points=[r["centre"] for r in rows],
                       masks=masks)
    transform = (frame if frame is not None else PixelFrame(size, tuple(scene.image_size))).to_dict()
    listing = {"input": source, "input_size": list(size), "working_size": list(scene.image_size),
               "pixel_frame": frame_text, "input_transform": transform, "objects": rows}
    summary = {"mode": "list", "input": source, "input_size": list(size), "image_size": list(scene.image_size),
               "input_transform": transform, "warnings": list(warnings or []),
               "objects": {"source": [r["id"] for r in rows],
                           "with_geometry": [r["id"] for r in rows if r["template"] is not None]},
               "checkpoints": checkpoints, "timings_ms": times, "proposals": proposals_record(scene),
               "config": config_record(cfg), "camera": camera_record(cfg)}
    if boxes:
        summary["boxes"] = list(boxes.values())
    with staged_directory(out, MARKER, bool(cfg.overwrite), owned=True, **_output_rules(cfg)) as tmp:
        write_json_atomic(tmp / "objects.json", listing)
        write_png_atomic(tmp / "objects.png", drawn)
        summary["outputs"] = ["objects.json", "objects.png", MARKER]
        write_json_atomic(tmp / MARKER, summary)
    return summary


def _input_masks(scene: Any, rows: list[dict], boxes: dict, frame: Any, size: tuple[int, int]) -> list:
    """Per listed row, the object's mask at the input's resolution where it was named by a box (else None)."""
    from sdn3d.editing.frame import PixelFrame, upsample_ids

    table = scene.objects
    ids = (table.mask.long() * table.instance_id[:, None, None]).amax(0) if len(table) else None
    if ids is None:
        return [None] * len(rows)
    transform = frame if frame is not None and tuple(frame.input_size) == size else PixelFrame(size, scene.image_size)
    big = upsample_ids(ids, transform).numpy()
    return [big == r["id"] if r["id"] in boxes else None for r in rows]


def _write_outputs(out: Path, overwrite: bool, result: EditResult, summary: dict, diagnostics: bool = True,
                   rules: dict[str, Any] | None = None) -> None:
    """Write the output directory all at once (see the module doc); adds ``summary['outputs']`` (every file
    written: what a later run may replace). ``rules``: :func:`_output_rules`."""
    from sdn3d.editing.photo.settings import source_picture
    from sdn3d.io import write_json_atomic, write_png_atomic
    from sdn3d.scene.io import save_scene

    gen = to_uint8(result.generated) if result.generated is not None else None
    with staged_directory(out, MARKER, overwrite, owned=True, **(rules or {"listed_in": "outputs"})) as tmp:
        if gen is not None:
            write_png_atomic(tmp / "generated.png", gen)
        write_png_atomic(tmp / "edited.png", result.edited)
        if result.source_map is not None:
            write_png_atomic(tmp / "maps" / "photo_source.png", source_picture(result.source_map))
        if result.region is not None:
            write_png_atomic(tmp / "maps" / "edit_region.png", result.region.numpy().astype(np.uint8) * 255)
        save_scene(result.scene, tmp / "scene.json")
        save_scene(result.edited_scene, tmp / "edited_scene.json")
        if diagnostics:
            _write_diagnostics(tmp, result, gen)
        summary["outputs"] = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*")
                                    if p.is_file() and p.name != OWNER_FILE) + [MARKER]
        write_json_atomic(tmp / MARKER, summary)


def _write_diagnostics(tmp: Path, result: EditResult, gen: np.ndarray) -> None:
    """``diagnostics=true``: the source and reconstruction pictures, every map, the overview grid, the glTF scenes."""
    from sdn3d.export import export_gltf
    from sdn3d.io import write_png_atomic

    scene, edited_scene = result.scene, result.edited_scene
    pictures = {"source": _map_pictures(result.source_maps, scene.class_list),
                "edited": _map_pictures(result.edited_maps, scene.class_list)}
    src, rec = to_uint8(result.derendered.input.image), to_uint8(result.reconstruction)
    write_png_atomic(tmp / "source.png", src)
    write_png_atomic(tmp / "reconstruction.png", rec)
    for which, maps in pictures.items():
        for kind, picture in maps.items():
            write_png_atomic(tmp / "maps" / f"{which}_{kind}.png", picture)
    s, e = pictures["source"], pictures["edited"]
    write_png_atomic(tmp / "overview.png", _grid([[src, rec, gen], [s["label"], s["instance"], e["instance"]],
                                                  [s["normal"], e["normal"], e["pose"]]]))
    export_gltf(scene, tmp / "scene.glb")
    export_gltf(edited_scene, tmp / "edited_scene.glb")


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry point: ``sdn3d-edit [overrides...]``; returns the exit status. As the program itself (``argv``
    None: the console script, ``python -m sdn3d.cli.edit``) it ends the process once done (:func:`_end_process`)."""
    import atexit

    atexit.register(gc.freeze)  # the exit's collections then skip the ~10^6 objects torch & co. made: ~0.5 s CPU
    program = argv is None
    if program:  # the process ends with this call (_end_process): no collection walks what exists now (0.08 CPU s)
        gc.freeze()
        _keep_freed_memory()
    argv = list(sys.argv[1:] if argv is None else argv)
    if print_help_if_asked(argv, __doc__, "edit"):
        return 0
    code = run_cli("edit", _main, argv)
    if program:
        _end_process(code)
    return code


def _keep_freed_memory() -> None:
    """Have glibc's malloc keep the memory the call frees for its next allocations, instead of giving it back to the
    system and faulting it in again, page by page (issue 40: 0.1 CPU s of system time of a 624x192 call with 10
    boxes, a fifth of its page faults). By default every block over a threshold that adapts up to the largest one
    freed (a picture's maps, a batch of crops) is a fresh mapping, unmapped when freed, and the top of the heap is
    trimmed; here blocks up to 32 MB (glibc's limit) come from the heap, which is not trimmed. The process ends with
    the call (:func:`_end_process`). Nothing computed changes: torch aligns every tensor itself."""
    import ctypes

    if not sys.platform.startswith("linux"):
        return
    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:
        return
    if not hasattr(libc, "gnu_get_libc_version"):  # not glibc: its malloc has other settings
        return
    m_trim_threshold, m_mmap_threshold = -1, -3  # malloc.h
    libc.mallopt(m_mmap_threshold, 32 * 2**20)
    libc.mallopt(m_trim_threshold, 2**31 - 1)


def _end_process(code: int) -> NoReturn:
    """End the process with ``code`` now: every output is written and closed, the lock given back, and the
    interpreter's teardown (freeing every module's objects, torch's included) would cost 0.15 CPU s of each call and
    write nothing (issue 40). The log handlers and the standard streams are flushed first."""
    import logging

    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):  # a closed pipe: nothing more to say
            stream.flush()
    os._exit(code)


def _output_lock(cfg: Any) -> Any:
    """The lock that makes this run ``output_dir``'s only writer (:func:`sdn3d.io.writer_lock`, a
    ``.<name>.lock`` file beside it naming this process), taken once the directory is known to be writable."""
    from sdn3d.io import check_writable, writer_lock

    out = Path(str(cfg.output_dir)).expanduser().resolve()
    check_writable(out)
    return writer_lock(out.parent / f".{out.name}.lock", f"output_dir {str(out)!r}")


def _main(argv: list[str]) -> int:
    cfg = compose_config(argv, "edit")
    with _output_lock(cfg):  # a second sdn3d-edit into the same output_dir meanwhile: a clear error, exit 2
        summary = run_edit(cfg)
    times = summary["timings_ms"]
    if summary.get("mode") == "list":
        print(f"sdn3d-edit: listed {len(summary['objects']['source'])} object(s); wrote objects.json and "
              f"objects.png to {summary['config']['output_dir']} (derender {times['derender_ms']:.0f} ms)")
        return 0
    width, height = summary["compose"]["output_size"]
    stages = ", ".join(f"{name} {times[key]:.0f} ms" for name, key in (
        ("derender", "derender_ms"), ("edit", "edit_ms"), ("render", "render_ms"), ("photo", "photo_ms"),
        ("compose", "compose_ms")) if key in times)
    print(f"sdn3d-edit: {len(summary['ops'])} edit(s) applied; wrote {summary['config']['output_dir']} "
          f"(edited.png {width}x{height}, appearance {summary['appearance']}"
          + (f", compose {summary['compose']['mode']}" if summary["appearance"] is Appearance.GENERATOR else "")
          + f"; {stages})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
