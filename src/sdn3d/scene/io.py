"""Storage of a :class:`~sdn3d.scene.code.SceneCode`: :func:`save_scene` / :func:`load_scene`.

``<name>.json`` holds the format tag ``sdn3d-scene``, the version, the intrinsics and the per-object
scalars as exact float64 reprs; ``<name>.npz`` holds the semantic map, phi, codes and masks, and its
SHA-256 is recorded in the JSON. Both are written atomically. Reading is lossless and checks every
field, raising :class:`~sdn3d.scene.code.SceneFormatError`. Kept apart from :mod:`sdn3d.scene.code` (the data
model), which imports this module inside ``save`` / ``load`` because this one imports its classes.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import torch

from sdn3d.io import write_bytes_atomic, write_json_atomic
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.templates import TEMPLATE_NAMES
from sdn3d.scene.code import SCENE_FORMAT, SCENE_VERSION, ObjectTable, SceneCode, SceneFormatError, meta_json

__all__ = ["load_scene", "save_scene"]


def save_scene(scene: SceneCode, path: str | os.PathLike) -> Path:
    """Write ``<path>.json`` and ``<path>.npz`` (suffix replaced), atomically; returns the JSON path."""
    json_path, npz_path = Path(path).with_suffix(".json"), Path(path).with_suffix(".npz")
    obj = scene.objects
    buffer = io.BytesIO()
    np.savez_compressed(
        buffer,
        semantic=scene.semantic.cpu().numpy().astype(np.uint8),
        phi=obj.phi.cpu().numpy(),
        code=obj.code.cpu().numpy(),
        masks=obj.mask[obj.has_mask].cpu().numpy(),
        background_codes=scene.background_codes.cpu().numpy(),
    )
    data = buffer.getvalue()
    rows = [
        {"instance_id": int(obj.instance_id[i]), "class_id": int(obj.class_id[i]),
         "template_id": int(obj.template_id[i]),
         "template": TEMPLATE_NAMES[int(obj.template_id[i])] if 0 <= obj.template_id[i] < len(TEMPLATE_NAMES)
         else None,
         "dims": obj.dims[i].tolist(), "ry": float(obj.ry[i]), "location": obj.location[i].tolist(),
         "has_mask": bool(obj.has_mask[i]), "observed": bool(obj.observed[i])}
        for i in range(len(obj))
    ]
    header = {"format": SCENE_FORMAT, "version": SCENE_VERSION, "image_size": list(scene.image_size),
              "intrinsics": scene.intrinsics.to_dict(), "classes": scene.classes, "code_dim": scene.code_dim,
              "arrays": {"file": npz_path.name, "sha256": hashlib.sha256(data).hexdigest()},
              "meta": meta_json(scene.meta), "objects": rows}
    write_bytes_atomic(npz_path, data)
    write_json_atomic(json_path, header)
    return json_path


def _read_scene(json_path: Path) -> SceneCode:
    """Read the scene whose JSON file is ``json_path`` (see :func:`load_scene`)."""
    def fail(field: str, problem: str, where: Path = json_path) -> SceneFormatError:
        return SceneFormatError(f"{where}: field {field!r}: {problem}")

    if not json_path.is_file():
        raise SceneFormatError(f"{json_path}: scene file not found")
    try:
        head = json.loads(json_path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise SceneFormatError(f"{json_path}: not a JSON scene file ({exc})") from exc
    if not isinstance(head, dict):
        raise fail("format", f"expected a JSON object, got {type(head).__name__}")
    if head.get("format") != SCENE_FORMAT:
        raise fail("format", f"expected {SCENE_FORMAT!r}, got {head.get('format')!r}")
    if head.get("version") != SCENE_VERSION:
        raise fail("version", f"unsupported version {head.get('version')!r} (this sdn3d reads {SCENE_VERSION})")

    def get(key: str, kind: type | tuple[type, ...], container: dict = head, prefix: str = "") -> Any:
        if key not in container:
            raise fail(prefix + key, "missing")
        value = container[key]
        if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
            raise fail(prefix + key, f"expected {getattr(kind, '__name__', kind)}, got {value!r}")
        return value

    try:
        intrinsics = Intrinsics(**get("intrinsics", dict))
    except (TypeError, ValueError) as exc:
        raise fail("intrinsics", str(exc)) from exc
    if get("image_size", list) != list(intrinsics.size[::-1]):
        raise fail("image_size", f"{head['image_size']} does not match the intrinsics' {list(intrinsics.size[::-1])}")
    arrays = get("arrays", dict)
    npz_path = json_path.parent / get("file", str, arrays, "arrays.")
    if not npz_path.is_file():
        raise fail("arrays.file", f"array file {npz_path} not found")
    data = npz_path.read_bytes()
    if hashlib.sha256(data).hexdigest() != get("sha256", str, arrays, "arrays."):
        raise fail("arrays.sha256", f"{npz_path.name} does not match the recorded checksum (mixed saves?)")
    with np.load(io.BytesIO(data), allow_pickle=False) as npz:
        missing = {"semantic", "phi", "code", "masks", "background_codes"} - set(npz.files)
        if missing:
            raise fail(sorted(missing)[0], "array missing", npz_path)
        arr = {k: torch.from_numpy(npz[k].copy()) for k in npz.files}
    rows = get("objects", list)
    for i, row in enumerate(rows):
        if not isinstance(row, dict):
            raise fail(f"objects[{i}]", "expected an object")
        for key, kind in (("instance_id", int), ("template_id", int), ("dims", list), ("ry", (int, float)),
                          ("location", list), ("has_mask", bool), ("observed", bool)):
            get(key, kind, row, f"objects[{i}].")
        for key in ("dims", "location"):
            if len(row[key]) != 3 or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in row[key]):
                raise fail(f"objects[{i}].{key}", f"expected 3 numbers, got {row[key]!r}")
    n, (height, width) = len(rows), intrinsics.size
    has_mask = torch.tensor([r["has_mask"] for r in rows], dtype=torch.bool)
    masks = torch.zeros(n, height, width, dtype=torch.bool)
    if tuple(arr["masks"].shape) != (int(has_mask.sum()), height, width):
        expected = (int(has_mask.sum()), height, width)
        raise fail("masks", f"expected shape {expected}, got {tuple(arr['masks'].shape)}", npz_path)
    masks[has_mask] = arr["masks"].bool()
    try:
        table = ObjectTable(
            instance_id=torch.tensor([r["instance_id"] for r in rows], dtype=torch.long),
            template_id=torch.tensor([r["template_id"] for r in rows], dtype=torch.long),
            phi=arr["phi"].float(), dims=torch.tensor([r["dims"] for r in rows], dtype=torch.float64).reshape(n, 3),
            ry=torch.tensor([float(r["ry"]) for r in rows], dtype=torch.float64),
            location=torch.tensor([r["location"] for r in rows], dtype=torch.float64).reshape(n, 3),
            code=arr["code"].float(), mask=masks, has_mask=has_mask,
            observed=torch.tensor([r["observed"] for r in rows], dtype=torch.bool))
        return SceneCode(intrinsics, arr["semantic"].long(), get("classes", str), table, arr["background_codes"],
                         get("meta", dict))
    except ValueError as exc:
        raise SceneFormatError(f"{json_path}: {exc}") from exc


def load_scene(path: str | os.PathLike) -> SceneCode:
    """Read a scene written by :func:`save_scene` (``path``: the JSON file, or the same stem).

    Raises:
        SceneFormatError: naming the file and the field, for a missing file, another format,
            an unknown version, a checksum mismatch or a malformed field.
    """
    return _read_scene(Path(path).with_suffix(".json"))
