"""On-disk cache of predicted generator inputs: the maps the textural branch trains on (issue 18).

3D-SDN's textural branch learns to render the *other branches' outputs*: per frame, the semantic
branch's labels and proposals and the geometric branch's templates, FFD and poses, composed into
the instance, label, normal and pose maps by the same code that draws an edit
(:func:`sdn3d.scene.maps.scene_maps`). Computing them takes two network forwards and a raster pass
per frame, so they are computed once (:func:`sdn3d.predicted_maps.build_predicted_maps`) and kept
here. This module only reads and writes the format; it imports nothing above the data readers.

Layout of one cache (a directory named after its key, the hash of everything it was computed from)::

    <cache_root>/<part>-<key>/manifest.json   format, key, inputs, frames: {frame key: {file, sha256}}
    <cache_root>/<part>-<key>/00000.npz ...   one frame: semantic (H, W) uint8, instance (H, W) int32,
                                              normal (3, H, W) float16, pose_bin (H, W) int8 (-1: none)

A cache whose inputs differ lives in another directory (new checkpoints or data give a new key, so
it is rebuilt, never reused). A manifest that does not match its directory's key or its inputs, a
missing frame, or a frame file whose bytes differ from the recorded sha256 is an error that names
the file: never silently reused.
"""

from __future__ import annotations

import hashlib
import io
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import Tensor

from sdn3d.errors import UserInputError
from sdn3d.io import write_bytes_atomic, write_json_atomic

__all__ = [
    "MAP_CACHE_FORMAT",
    "MapCacheError",
    "FrameMaps",
    "MapCache",
    "MapCacheWriter",
    "cache_key",
    "encode_frame_maps",
]

MAP_CACHE_FORMAT = "sdn3d-predicted-maps/1"
MANIFEST = "manifest.json"


class MapCacheError(UserInputError):
    """A predicted-map cache file is corrupt, stale or incomplete (the message names the file)."""


@dataclass(frozen=True)
class FrameMaps:
    """Predicted generator inputs of one frame at the working size ``(H, W)``.

    Attributes:
        semantic: ``(H, W)`` int64 class indices (object pixels carry their object's class).
        instance: ``(H, W)`` int64 instance ids ``class * 1000 + k``, 0 = none.
        normal: ``(3, H, W)`` float32 camera-frame normals of the visible rendered surface, 0 elsewhere.
        pose_bin: ``(H, W)`` int64 observation-angle bin of the object drawn there, -1 = none.
    """

    semantic: Tensor
    instance: Tensor
    normal: Tensor
    pose_bin: Tensor

    @property
    def size(self) -> tuple[int, int]:
        """``(H, W)``."""
        return tuple(self.semantic.shape)  # type: ignore[return-value]


def cache_key(inputs: dict[str, Any]) -> str:
    """Hex key (16 digits) of a cache's inputs: the sha256 of their canonical JSON."""
    text = json.dumps(inputs, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def encode_frame_maps(maps: FrameMaps) -> bytes:
    """``maps`` as the bytes of one cache ``.npz`` (compressed)."""
    buf = io.BytesIO()
    np.savez_compressed(
        buf,
        semantic=maps.semantic.numpy().astype(np.uint8),
        instance=maps.instance.numpy().astype(np.int32),
        normal=maps.normal.numpy().astype(np.float16),
        pose_bin=maps.pose_bin.numpy().astype(np.int8),
    )
    return buf.getvalue()


def _decode(path: Path, data: bytes, size: tuple[int, int]) -> FrameMaps:
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in ("semantic", "instance", "normal", "pose_bin")}
    except (KeyError, ValueError, OSError, EOFError) as exc:
        raise MapCacheError(f"{path}: not a readable predicted-map file ({exc}); delete the cache directory "
                            f"{path.parent} to rebuild it") from exc
    h, w = size
    want = {"semantic": (h, w), "instance": (h, w), "normal": (3, h, w), "pose_bin": (h, w)}
    for name, shape in want.items():
        if arrays[name].shape != shape:
            raise MapCacheError(f"{path}: {name} has shape {arrays[name].shape}, expected {shape} (the working size "
                                f"{w}x{h}); delete {path.parent} to rebuild the cache")
    return FrameMaps(
        semantic=torch.from_numpy(arrays["semantic"].astype(np.int64)),
        instance=torch.from_numpy(arrays["instance"].astype(np.int64)),
        normal=torch.from_numpy(arrays["normal"].astype(np.float32)),
        pose_bin=torch.from_numpy(arrays["pose_bin"].astype(np.int64)),
    )


class MapCache:
    """One complete cache directory (module doc), checked against the inputs it must have come from.

    Args:
        directory: the cache directory (``<cache_root>/<part>-<key>``).
        inputs: what the caller would compute it from; must equal the manifest's.
        frame_keys: the frames the caller needs; every one must be in the manifest.
        size: working size ``(W, H)``.

    Raises:
        MapCacheError: no manifest, another format, other inputs or key, or a needed frame missing.
    """

    def __init__(self, directory: str | Path, inputs: dict[str, Any], frame_keys: list[str],
                 size: tuple[int, int]) -> None:
        self.directory = Path(directory)
        path = self.directory / MANIFEST
        try:
            manifest = json.loads(path.read_text())
        except FileNotFoundError as exc:
            raise MapCacheError(f"{path}: missing; the cache directory is incomplete, delete it to rebuild") from exc
        except (OSError, ValueError) as exc:
            raise MapCacheError(f"{path}: unreadable ({exc}); delete {self.directory} to rebuild the cache") from exc
        if not isinstance(manifest, dict) or manifest.get("format") != MAP_CACHE_FORMAT:
            raise MapCacheError(f"{path}: not a {MAP_CACHE_FORMAT} manifest; delete {self.directory} to rebuild")
        key = cache_key(inputs)
        if manifest.get("key") != key or manifest.get("inputs") != json.loads(json.dumps(inputs)):
            raise MapCacheError(f"{path}: stale: computed from other checkpoints, data or settings than this run's "
                                f"(key {manifest.get('key')!r}, expected {key!r}); delete {self.directory}")
        frames = manifest.get("frames")
        if not isinstance(frames, dict):
            raise MapCacheError(f"{path}: 'frames' must be a mapping; delete {self.directory} to rebuild")
        missing = [k for k in frame_keys if k not in frames]
        if missing:
            raise MapCacheError(f"{path}: {len(missing)} frame(s) missing (first {missing[0]!r}); delete "
                                f"{self.directory} to rebuild")
        self.frames: dict[str, dict[str, str]] = frames
        self.size = (int(size[1]), int(size[0]))

    def load(self, frame_key: str) -> FrameMaps:
        """The maps of ``frame_key``; its file's bytes must match the recorded sha256."""
        entry = self.frames[frame_key]
        path = self.directory / entry["file"]
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise MapCacheError(f"{path}: cannot read ({exc}); delete {self.directory} to rebuild the cache") from exc
        if hashlib.sha256(data).hexdigest() != entry["sha256"]:
            raise MapCacheError(f"{path}: corrupt (its sha256 differs from the manifest's); delete {self.directory} "
                                "to rebuild the cache")
        return _decode(path, data, self.size)


class MapCacheWriter:
    """Writes a cache frame by frame (memory stays one frame), the manifest last.

    Frame files and the manifest are each written atomically; a directory without a manifest is
    incomplete and :class:`MapCache` refuses it.

    Args:
        directory: the new cache directory (created).
        inputs: what the maps are computed from (stored in the manifest with their key).
    """

    def __init__(self, directory: str | Path, inputs: dict[str, Any]) -> None:
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.inputs = inputs
        self.frames: dict[str, dict[str, str]] = {}

    def add(self, frame_key: str, maps: FrameMaps) -> None:
        data = encode_frame_maps(maps)
        name = f"{len(self.frames):05d}.npz"
        write_bytes_atomic(self.directory / name, data)
        self.frames[frame_key] = {"file": name, "sha256": hashlib.sha256(data).hexdigest()}

    def finish(self) -> Path:
        write_json_atomic(self.directory / MANIFEST, {"format": MAP_CACHE_FORMAT, "key": cache_key(self.inputs),
                                                      "inputs": self.inputs, "frames": self.frames})
        return self.directory
