"""The textural branch's training inputs from the other branches' predictions (3D-SDN's stack; issue 18).

Per frame: :func:`~sdn3d.derender.derender` with the trained semantic branch's labels and proposals
(``proposals='semantic'``: no ground truth is read) and the geometric branch's template, FFD and pose,
then :func:`~sdn3d.scene.maps.scene_maps`: the instance, label, normal and pose maps of the unedited
scene, exactly the maps the generator gets when it draws an edit. On Cityscapes, where the geometric
branch is refined per image (the paper's setting), pass ``refine``.

The maps go to a :mod:`sdn3d.data.map_cache` directory keyed by the content hashes of both checkpoints,
the frames (key, file size and modification time of each RGB file), the working size and the settings:
other checkpoints or data give another directory, so a cache is computed once and never reused stale.

    >>> from sdn3d.predicted_maps import map_cache_inputs  # doctest: +SKIP
"""

from __future__ import annotations

import functools
import logging
import os
import shutil
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import torch

from sdn3d.data.frames import load_frame
from sdn3d.data.map_cache import MANIFEST, MAP_CACHE_FORMAT, FrameMaps, MapCache, MapCacheWriter, cache_key
from sdn3d.data.records import FrameRecord
from sdn3d.derender import derender
from sdn3d.geometric.refine import RefineSettings
from sdn3d.io import file_sha256
from sdn3d.models import Models
from sdn3d.scene.maps import scene_maps

__all__ = ["map_cache_inputs", "predict_frame_maps", "build_predicted_maps"]

log = logging.getLogger(__name__)


@functools.lru_cache(maxsize=8)
def _checkpoint_sha256(path: str, size: int, mtime_ns: int) -> str:
    """SHA-256 of a checkpoint file, once per process for the same file version (a run's train, val and test
    caches share both checkpoints: 130 MB each, hashed once instead of three times)."""
    return file_sha256(path)


def _file_key(path: str | os.PathLike) -> str:
    st = os.stat(path)
    return _checkpoint_sha256(os.path.realpath(path), st.st_size, st.st_mtime_ns)


def _frames_fingerprint(records: Sequence[FrameRecord]) -> list[list[Any]]:
    out = []
    for r in records:
        st = os.stat(r.rgb_path)
        out.append([r.key, st.st_size, st.st_mtime_ns])
    return out


def map_cache_inputs(records: Sequence[FrameRecord], image_size: tuple[int, int], semantic: str | os.PathLike,
                     geometric: str | os.PathLike, min_pixels: int = 64,
                     refine: RefineSettings | None = None) -> dict[str, Any]:
    """What a cache is computed from (its key is their hash): checkpoint sha256s, frames, size, settings."""
    return {
        "format": MAP_CACHE_FORMAT,
        "semantic_sha256": _file_key(semantic),
        "geometric_sha256": _file_key(geometric),
        "image_size": [int(image_size[0]), int(image_size[1])],
        "min_pixels": int(min_pixels),
        "refine": None if refine is None else {"iterations": refine.iterations, "lr": refine.lr,
                                                "params": list(refine.params), "ffd_reg": refine.ffd_reg,
                                                "sigma": refine.sigma},
        "frames": _frames_fingerprint(records),
    }


def predict_frame_maps(record: FrameRecord, image_size: tuple[int, int], models: Models, min_pixels: int = 64,
                       refine: RefineSettings | None = None) -> FrameMaps:
    """The predicted generator inputs of one frame (module doc) at ``image_size = (W, H)``."""
    frame = load_frame(record, image_size, semantic=False, instances=False)
    with torch.no_grad():
        scene = derender(frame.image, frame.intrinsics, models, proposals="semantic", min_pixels=min_pixels,
                         refine=refine)
        maps = scene_maps(scene)
    pose = maps.pose
    pose_bin = torch.where(pose.sum(0) > 0, pose.argmax(0), -1)
    return FrameMaps(semantic=scene.semantic.long().cpu(), instance=maps.instance.long().cpu(),
                     normal=maps.normal.float().cpu(), pose_bin=pose_bin.long().cpu())


def build_predicted_maps(records: Sequence[FrameRecord], image_size: tuple[int, int], semantic: str | os.PathLike,
                         geometric: str | os.PathLike, cache_root: str | os.PathLike, part: str, *,
                         min_pixels: int = 64, refine: RefineSettings | None = None,
                         progress: Callable[[int, int], None] | None = None) -> MapCache:
    """The cache of ``records``' predicted maps: opened if it exists, else computed and written.

    Args:
        records: the frames (one part of a dataset).
        image_size: working size ``(W, H)``.
        semantic, geometric: the branches' checkpoints (Lightning or inference export).
        cache_root: where caches live; this one is ``<cache_root>/<part>-<key>``.
        part: a name for the directory (``train``, ``val``, ``test``).
        min_pixels, refine: as :func:`~sdn3d.derender.derender`.
        progress: called with ``(done, total)`` after each frame.

    Raises:
        MapCacheError: an existing cache directory of this key that is corrupt or incomplete.
    """
    inputs = map_cache_inputs(records, image_size, semantic, geometric, min_pixels, refine)
    keys = [r.key for r in records]
    directory = Path(cache_root) / f"{part}-{cache_key(inputs)}"
    if (directory / MANIFEST).exists():
        log.info("predicted maps of %d %s frames: reusing %s", len(records), part, directory)
        return MapCache(directory, inputs, keys, image_size)
    models = Models.from_checkpoints(semantic=semantic, geometric=geometric)
    staging = directory.with_name(f".{directory.name}.partial-{os.getpid()}")
    shutil.rmtree(staging, ignore_errors=True)
    writer = MapCacheWriter(staging, inputs)
    start = time.perf_counter()
    for i, record in enumerate(records):
        writer.add(record.key, predict_frame_maps(record, image_size, models, min_pixels, refine))
        if progress is not None:
            progress(i + 1, len(records))
    writer.finish()
    if directory.exists():  # an incomplete directory of this key (no manifest): replaced
        shutil.rmtree(directory)
    os.replace(staging, directory)
    log.info("predicted maps of %d %s frames in %.1f s: %s", len(records), part, time.perf_counter() - start,
             directory)
    return MapCache(directory, inputs, keys, image_size)
