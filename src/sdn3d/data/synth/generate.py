"""Generate a synthetic dataset in the Virtual KITTI 1.3.1 format (the project's embedded data).

:func:`generate_dataset` renders every ``<world>/<variation>`` sequence of a
:class:`SynthConfig` and writes the Virtual KITTI 1.3.1 tree (see ``writer.py``), the editing
benchmark ``vkitti_edit_benchmark.json`` (3D-SDN format, see ``edits.py``) and
``synth_manifest.json``. Edit targets are frames of their own sequence numbered after the
regular frames: a sequence of ``F`` frames and ``E`` edit pairs holds frames ``0 .. F-1``
(the camera drives on) and ``F .. F+E-1`` (edited copies of a source frame, same camera).
A pair that cannot be drawn is written as an entry without operations; the manifest's ``benchmark_entries``
counts each kind's entries asked for and made, with why any are missing, and a short kind is warned about on
stderr (:mod:`sdn3d.data.synth.entry_report`).

The write is all-or-nothing: everything goes to a temporary sibling directory that is renamed
onto ``output_dir`` at the end (after ``_SUCCESS`` is written in it; :func:`sdn3d.io.staged_directory`).
An existing non-empty ``output_dir`` is refused unless ``overwrite``, and even then unless it is an earlier
dataset of this generator (it holds ``synth_manifest.json``); it is then replaced only once the new tree
is complete. The working directory, the home directory, their parents and ``/`` are never replaced.
While it is written the temporary tree holds an owner record (this process and host): a run that was
killed (SIGKILL, OOM) leaves it behind, and the next run into the same ``output_dir`` removes it.
Sequences whose variations share the camera (clone, morning, sunset, overcast, fog, rain) are rendered
together: each frame's geometry once, its lighting once per variation (:func:`generate_sequences`), with the
same bytes as one at a time. Inside the staging tree files are written without a per-file fsync and the tree is
flushed to disk once, before it is renamed (``writer.write_staged``). :func:`generate_dataset` ``progress=``
reports frames done, frames/s and the ETA on stderr (``sdn3d-synth`` does).
Rendering processes (``workers > 1``) end with the process that started them (Linux: the kernel
SIGKILLs them when it dies, ``prctl(PR_SET_PDEATHSIG)``; elsewhere they poll for it), so a killed run
leaves no process behind.

The same config gives byte-identical files on one software stack: every random draw comes
from a numpy Generator seeded by ``(seed, world[, variation, frame])``, independently of worker count.
Across stacks (other numpy / PyTorch builds, other CPUs) labels, object tables, cameras and the edit
benchmark stay identical, while a few RGB and depth pixels may differ by floating-point rounding in the
shading (measured: at most 8 pixels per frame, docs/results/2026-11-22_h100/README.md).
"""

from __future__ import annotations

import ctypes
import functools
import math
import multiprocessing
import numbers
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field
from multiprocessing.queues import Queue
from pathlib import Path
from typing import Any, TextIO

import numpy as np
import torch

from sdn3d.data.edit_benchmark import BenchmarkEntry, save_edit_benchmark
from sdn3d.data.synth.class_stats import write_class_statistics
from sdn3d.data.synth.counterfactual import (
    PAIRS_DIR,
    PAIRS_FORMAT,
    PAIRS_NAME,
    SHADOW_THRESHOLD,
    Target,
    deleted,
    eligible_targets,
    full_resolution_centre,
    mask_png_bytes,
    pair_masks,
    turn_overlaps,
    turned,
)
from sdn3d.data.synth.edits import (
    DEFAULT_DELETE_SHARE,
    MAX_HIDDEN_FRACTION,
    OccluderCandidates,
    hidden_min_pixels,
    occluder_candidates,
    remove_occluder,
    sample_edit,
)
from sdn3d.data.synth.entry_report import (
    MANIFEST_KEY,
    Missing,
    MissingEntry,
    counts_json,
    manifest_counts,
    shortfall_lines,
)
from sdn3d.data.synth.layout import (
    CAMERA_YAW_DEG,
    VARIATIONS,
    VEHICLE_SOURCES,
    FrameObjects,
    World,
    build_world,
    frame_objects,
    rng_for,
)
from sdn3d.data.synth.progress import FrameProgress
from sdn3d.data.synth.scene_render import RenderedFrame, light_frame, render_geometry
from sdn3d.data.synth.stats import ObjectStats
from sdn3d.data.synth.writer import SequenceWriter, frame_path, png_bytes, write_staged
from sdn3d.errors import UserInputError
from sdn3d.io import process_alive, staged_directory, write_json_atomic, write_text_atomic
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.math3d.camera import VKITTI_INTRINSICS, Intrinsics

__all__ = [
    "SynthConfig",
    "SynthConfigError",
    "generate_dataset",
    "generate_sequences",
    "sequence_groups",
    "SequenceSummary",
    "BENCHMARK_NAME",
    "MANIFEST_NAME",
]

BENCHMARK_NAME = "vkitti_edit_benchmark.json"
MANIFEST_NAME = "synth_manifest.json"
#: Edits are re-drawn (at most this many times) until every modified car is visible in the target.
_EDIT_ATTEMPTS = 5


class SynthConfigError(UserInputError):
    """A bad :class:`SynthConfig` field (a ``conf/synth.yaml`` setting); the message names the field."""


def _got(value: object) -> str:
    return f"{value!r} ({type(value).__name__})"


def _integer(name: str, value: object, minimum: int | None = None) -> int:
    """``value`` as a plain int, if it is an integer (not a bool, float or string) ``>= minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        bound = "" if minimum is None else f" >= {minimum}"
        raise SynthConfigError(f"{name} must be an integer{bound}, got {_got(value)}")
    if minimum is not None and value < minimum:
        raise SynthConfigError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def _integer_pair(name: str, value: object, form: str) -> tuple[int, int]:
    """``value`` as two plain ints (a list or tuple of two integers); ``form`` names them in the message."""
    listed = isinstance(value, (Sequence, np.ndarray)) and not isinstance(value, (str, bytes))
    if (not listed or len(value) != 2
            or any(isinstance(v, bool) or not isinstance(v, numbers.Integral) for v in value)):
        shown = list(value) if listed else value
        raise SynthConfigError(f"{name} must be {form}: a list of two integers, got {shown!r}")
    return int(value[0]), int(value[1])


def _names(name: str, value: object, example: str) -> tuple[str, ...]:
    """``value`` as a tuple of names: a list or tuple of strings (integers are written out)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise SynthConfigError(f"{name} must be a list like {example}, got {_got(value)}")
    bad = [v for v in value if isinstance(v, bool) or not isinstance(v, (str, numbers.Integral))]
    if bad:
        raise SynthConfigError(f"{name} must be a list of names like {example}, got {list(value)!r}")
    return tuple(str(v) for v in value)


@dataclass(frozen=True)
class SynthConfig:
    """What to generate (``conf/synth.yaml`` documents every field).

    Attributes:
        output_dir: dataset root to create.
        seed: dataset seed.
        image_size: ``(width, height)``; intrinsics are ``VKITTI_INTRINSICS.resized(width, height)``.
        worlds: 4-digit world names.
        variations: Virtual KITTI variation names.
        frames_per_sequence: regular frames per sequence.
        cars_per_frame: ``(min, max)`` cars placed along the 100 m ahead of the camera.
        edit_pairs: edit pairs per sequence (each adds one target frame).
        occluder_pairs: "occluder removed" pairs per sequence (each adds one target frame, after the edit pairs'):
            a car in front of a partly hidden one deleted (:func:`~sdn3d.data.synth.edits.occluder_candidates`).
        max_edit_operations: at most this many operations per pair.
        edit_delete_share: the chance that each car an edit pair picks is deleted rather than moved, turned or
            zoomed (:func:`~sdn3d.data.synth.edits.sample_edit`; 0.15, the default, draws the pairs it always drew).
            1.0 makes every edit pair a delete: a benchmark of deletes alone, whose few entries a mixed tree
            otherwise gives (about 7 a tree of 100 edit pairs).
        overwrite: replace a non-empty ``output_dir``.
        workers: processes rendering in parallel (1: in this process); the unit of work is a world's
            variations that share the camera (:func:`sequence_groups`: each frame's geometry is rendered once
            for them), so ``workers`` beyond the number of such groups do not help.
        threads: torch threads per process.
        vehicles: ``'heldout'`` (car bodies from the held-out vehicle family, :mod:`sdn3d.meshes.vehicle_family`)
            or ``'bank'`` (from the geometric branch's 8 templates: the data before the family existed).
        counterfactual_cars: target cars per sequence of the counterfactual pairs (:mod:`~sdn3d.data.synth.
            counterfactual`; 0, the default: none, and the dataset is what it was without the option).
        counterfactual_turns: the turn pairs' angles in degrees (each target gets one turned render per angle).
        counterfactual_delete: each target also gets a delete pair (the frame rendered without it).
        camera_height: the camera's height above the road in metres (None, the default: drawn per world in
            [1.50, 1.65] as before).
        camera_pitch: the camera's pitch in radians, positive looking down (Cityscapes' convention; 0, the default:
            level, as before). With either set, each sequence also gets a Cityscapes-style ``camera.json`` beside
            its frames (:func:`camera_json`); the extrinsicsgt rows are the pitched camera's, motgt's ``x3d y3d
            z3d`` the bottom-face centre in its frame and ``ry`` the yaw about the road's normal.
    """

    output_dir: str
    seed: int = 0
    image_size: tuple[int, int] = (624, 192)
    worlds: tuple[str, ...] = ("0001",)
    variations: tuple[str, ...] = ("clone",)
    frames_per_sequence: int = 10
    cars_per_frame: tuple[int, int] = (4, 12)
    edit_pairs: int = 2
    occluder_pairs: int = 1
    max_edit_operations: int = 3
    edit_delete_share: float = DEFAULT_DELETE_SHARE
    overwrite: bool = False
    workers: int = 1
    threads: int = 1
    vehicles: str = "heldout"
    counterfactual_cars: int = 0
    counterfactual_turns: tuple[float, ...] = (15, 45, 90, 180)
    counterfactual_delete: bool = True
    camera_height: float | None = None
    camera_pitch: float = 0.0

    def __post_init__(self) -> None:
        """Check every field's type and range (:class:`SynthConfigError` naming the field); normalise
        sequences to tuples and integers to plain ints."""

        def put(name: str, value: object) -> None:
            object.__setattr__(self, name, value)

        if isinstance(self.output_dir, bool) or not isinstance(self.output_dir, (str, os.PathLike)) \
                or not os.fspath(self.output_dir):
            raise SynthConfigError(f"output_dir must be a non-empty path, got {_got(self.output_dir)}")
        put("seed", _integer("seed", self.seed))
        width, height = _integer_pair("image_size", self.image_size, "[width, height]")
        if min(width, height) < 8:
            raise SynthConfigError(f"image_size must be [width, height], both >= 8, got {[width, height]}")
        put("image_size", (width, height))
        put("worlds", _names("worlds", self.worlds, "['0001', '0002']"))
        if not self.worlds or any(not (len(w) == 4 and w.isdigit()) for w in self.worlds):
            raise SynthConfigError(f"worlds must be a non-empty list of 4-digit names like '0001', "
                                   f"got {list(self.worlds)}")
        if len(set(self.worlds)) != len(self.worlds):
            raise SynthConfigError(f"worlds must not repeat, got {list(self.worlds)}")
        put("variations", _names("variations", self.variations, "[clone, fog]"))
        unknown = [v for v in self.variations if v not in VARIATIONS]
        if not self.variations or unknown or len(set(self.variations)) != len(self.variations):
            raise SynthConfigError(f"variations must be distinct names from {list(VARIATIONS)}, "
                                   f"got {list(self.variations)}")
        put("frames_per_sequence", _integer("frames_per_sequence", self.frames_per_sequence, 1))
        lo, hi = _integer_pair("cars_per_frame", self.cars_per_frame, "[min, max]")
        if lo < 0 or hi < lo:
            raise SynthConfigError(f"cars_per_frame must be [min, max] with 0 <= min <= max, got {[lo, hi]}")
        put("cars_per_frame", (lo, hi))
        put("edit_pairs", _integer("edit_pairs", self.edit_pairs, 0))
        put("occluder_pairs", _integer("occluder_pairs", self.occluder_pairs, 0))
        put("max_edit_operations", _integer("max_edit_operations", self.max_edit_operations, 1))
        share = self.edit_delete_share
        if isinstance(share, bool) or not isinstance(share, numbers.Real) or not 0.0 <= float(share) <= 1.0:
            raise SynthConfigError(f"edit_delete_share must be a number in [0, 1], got {_got(share)}")
        put("edit_delete_share", float(share))
        if self.frames_per_sequence + self.target_frames > 99999:
            raise SynthConfigError("frames_per_sequence + edit_pairs + occluder_pairs must fit 5-digit frame numbers "
                                   "(<= 99999)")
        if not isinstance(self.overwrite, (bool, np.bool_)):
            raise SynthConfigError(f"overwrite must be true or false, got {_got(self.overwrite)}")
        put("overwrite", bool(self.overwrite))
        put("workers", _integer("workers", self.workers, 1))
        put("threads", _integer("threads", self.threads, 1))
        if not isinstance(self.vehicles, str) or self.vehicles not in VEHICLE_SOURCES:
            raise SynthConfigError(f"vehicles must be one of {list(VEHICLE_SOURCES)}, got {_got(self.vehicles)}")
        put("counterfactual_cars", _integer("counterfactual_cars", self.counterfactual_cars, 0))
        turns = self.counterfactual_turns
        if (isinstance(turns, (str, bytes)) or not isinstance(turns, (Sequence, np.ndarray))
                or any(isinstance(a, bool) or not isinstance(a, numbers.Real) or not -360 < float(a) <= 360
                       for a in turns) or len(set(float(a) for a in turns)) != len(turns)):
            raise SynthConfigError("counterfactual_turns must be a list of distinct angles in degrees in (-360, 360], "
                                   f"like [15, 45, 90, 180], got {_got(turns)}")
        put("counterfactual_turns", tuple(int(a) if float(a).is_integer() else float(a) for a in turns))
        if not isinstance(self.counterfactual_delete, (bool, np.bool_)):
            raise SynthConfigError(f"counterfactual_delete must be true or false, "
                                   f"got {_got(self.counterfactual_delete)}")
        put("counterfactual_delete", bool(self.counterfactual_delete))
        height, pitch = self.camera_height, self.camera_pitch
        if height is not None and (isinstance(height, bool) or not isinstance(height, numbers.Real)
                                   or not 0.2 <= float(height) <= 10.0):
            raise SynthConfigError(f"camera_height must be null or metres in [0.2, 10], got {_got(height)}")
        put("camera_height", None if height is None else float(height))
        if isinstance(pitch, bool) or not isinstance(pitch, numbers.Real) or not abs(float(pitch)) <= 0.3:
            raise SynthConfigError(f"camera_pitch must be radians in [-0.3, 0.3] (positive looking down), "
                                   f"got {_got(pitch)}")
        put("camera_pitch", float(pitch))

    @property
    def first_test_frame(self) -> int:
        """First regular frame of the sequences' test part, where edit sources come from: the last 20 %
        (:func:`sdn3d.data.splits.paper_split`, at least the last frame)."""
        return min(math.floor(0.8 * self.frames_per_sequence + 1e-9), self.frames_per_sequence - 1)

    @property
    def target_frames(self) -> int:
        """Edit-target frames per sequence: the edit pairs' then the occluder-removed pairs'."""
        return self.edit_pairs + self.occluder_pairs

    @property
    def intrinsics(self) -> Intrinsics:
        width, height = self.image_size
        return VKITTI_INTRINSICS.resized(width, height)

    @property
    def camera_options(self) -> bool:
        """``camera_height`` or ``camera_pitch`` is set (not the defaults)."""
        return self.camera_height is not None or self.camera_pitch != 0.0

    def to_dict(self) -> dict:
        out = asdict(self)
        return {k: list(v) if isinstance(v, tuple) else v for k, v in out.items()}

    def recorded(self) -> dict:
        """The settings ``synth_manifest.json`` records as ``config``: what decides the data (not where it goes or
        how many processes write it); an option left off is left out, so a tree made before it existed reads the
        same. Whoever asks whether a tree was made with these settings compares this."""
        left_out = {"output_dir", "overwrite", "workers", "threads"}
        if not self.counterfactual_cars:
            left_out |= {"counterfactual_cars", "counterfactual_turns", "counterfactual_delete"}
        if not self.camera_options:
            left_out |= {"camera_height", "camera_pitch"}
        return {k: v for k, v in self.to_dict().items() if k not in left_out}


@dataclass
class SequenceSummary:
    """What one sequence wrote: frame and object-row counts, its benchmark entries and the pairs it asked for
    and could not make (each written as an entry without operations)."""

    world: str
    variation: str
    frames: int
    edit_frames: list[int]
    object_rows: int
    entries: list[BenchmarkEntry]
    counterfactual: list[dict] = field(default_factory=list)
    missing: list[MissingEntry] = field(default_factory=list)


@functools.lru_cache(maxsize=4)
def _world(seed: int, name: str, frames: int, cars: tuple[int, int], vehicles: str,
           camera_height: float | None = None, camera_pitch: float = 0.0) -> World:
    return build_world(seed, name, frames, cars, vehicles, camera_height, camera_pitch)


def camera_json(world: World, intrinsics: Intrinsics, yaw_deg: float) -> dict:
    """A Cityscapes-style ``camera.json`` of a sequence's camera (what ``sdn3d-edit input.camera=`` reads):
    ``intrinsic`` ``fx fy u0 v0`` at the generated size, ``extrinsic`` the camera in a vehicle frame (ISO 8855) on
    the road below it: ``z`` its height, ``pitch`` (positive looking down), ``roll`` 0, ``yaw`` the variation's turn
    (Cityscapes' yaw turns left, the variations' negative angles do), ``x y`` 0 and ``baseline`` 0 (no stereo)."""
    return {"extrinsic": {"baseline": 0.0, "pitch": world.camera.pitch, "roll": 0.0, "x": 0.0, "y": 0.0,
                          "yaw": -math.radians(yaw_deg), "z": world.camera.height},
            "intrinsic": {"fx": intrinsics.fx, "fy": intrinsics.fy, "u0": intrinsics.cx, "v0": intrinsics.cy}}


def _annotations(world: World, objects: FrameObjects, frame: RenderedFrame) -> dict[str, np.ndarray]:
    cars = world.cars
    dims = cars.dims[objects.track]
    bottom = objects.center + np.stack([np.zeros(len(objects)), dims[:, 1] / 2, np.zeros(len(objects))], 1)
    tilt = world.camera.tilt()  # a pitched camera: motgt's location is in its frame, the objects in the level one
    if tilt is not None:
        bottom = bottom @ tilt.T
    return {
        "tid": cars.tid[objects.track],
        "dims": dims,
        "bottom": bottom,
        "ry": objects.ry,
        "box": frame.stats.box,
        "truncr": frame.stats.truncr,
        "occupr": frame.stats.occupr,
        "visible_fraction": frame.stats.visible_fraction,
        "visible": frame.stats.visible,
        "moving": objects.moving,
        "model": np.array(cars.model, dtype=object)[objects.track] if len(cars) else np.zeros(0, object),
        "color": np.array(cars.color_name, dtype=object)[objects.track] if len(cars) else np.zeros(0, object),
        "category": np.array(cars.category, dtype=object)[objects.track] if len(cars) else np.zeros(0, object),
    }


def _frame_seed(cfg: SynthConfig, world: str, variation: str, frame: int) -> int:
    return int(rng_for(cfg.seed, world, variation, "frame", frame).integers(0, 2**31 - 1))


def _write(writer: SequenceWriter, index: int, frame: RenderedFrame, pose: np.ndarray, world: World,
           objects: FrameObjects, encoded: dict[tuple[str, int], bytes] | None = None) -> int:
    """Write one frame's files and rows (``encoded``: see ``SequenceWriter.write_frame``); returns its number
    of motgt rows (visible objects)."""
    writer.write_frame(index, frame.rgb, frame.class_map, frame.instance, frame.depth, pose,
                       _annotations(world, objects, frame), encoded)
    return int((frame.stats.visible > 0).sum())


def generate_sequences(root: Path, cfg: SynthConfig, world_name: str, variations: Sequence[str],
                       on_frame: Callable[[], None] | None = None) -> list[SequenceSummary]:
    """Render and write the ``<world>/<variation>`` sequences of ``variations`` (regular frames, then edit
    targets); ``on_frame()`` is called after each frame is written (progress reports).

    The variations must share the camera (the same ``CAMERA_YAW_DEG``: e.g. clone, morning, sunset, overcast,
    fog and rain): each frame's geometry (rasterization, surfaces, object statistics) is rendered once and
    lit once per variation (:func:`~sdn3d.data.synth.scene_render.light_frame`), the same bytes as rendering
    each sequence alone. Edit targets are drawn per variation, as before.
    """
    variations = tuple(variations)
    yaws = {CAMERA_YAW_DEG.get(v, 0.0) for v in variations}
    if len(yaws) != 1:
        raise ValueError(f"generate_sequences: variations {list(variations)} do not share one camera yaw")
    yaw = yaws.pop()
    world = _world(cfg.seed, world_name, cfg.frames_per_sequence, cfg.cars_per_frame, cfg.vehicles,
                   cfg.camera_height, cfg.camera_pitch)
    intrinsics = cfg.intrinsics
    if cfg.camera_options:
        for v in variations:
            write_json_atomic(Path(root) / "vkitti_1.3.1_rgb" / world_name / v / "camera.json",
                              camera_json(world, intrinsics, yaw))
    color_seed = int(rng_for(cfg.seed, "colors", world_name).integers(0, 2**31 - 1))
    writers = {v: SequenceWriter(Path(root), world_name, v, world.cars.tid, world.cars.category, color_seed=color_seed)
               for v in variations}
    rows = dict.fromkeys(variations, 0)
    rendered: list[tuple[FrameObjects, ObjectStats, np.ndarray]] = []
    for f in range(cfg.frames_per_sequence):
        objects = frame_objects(world, f, yaw)
        pose = world.camera.pose(f, yaw)
        geometry = render_geometry(world, objects, pose, intrinsics)
        encoded: dict[tuple[str, int], bytes] = {}  # scenegt / depth PNGs: the same for every variation here
        for v in variations:
            frame = light_frame(geometry, v, _frame_seed(cfg, world_name, v, f))
            rows[v] += _write(writers[v], f, frame, pose, world, objects, encoded)
            if on_frame is not None:
                on_frame()
        # Keep only what edit sampling needs (objects and statistics), not the images.
        rendered.append((objects, geometry.stats, pose))
    pairs = _counterfactual_pairs(Path(root), cfg, world, world_name, variations, rendered)
    summaries = []
    for v in variations:
        entries, edit_frames, edit_rows, missing = _edit_targets(writers[v], cfg, world, world_name, v, rendered,
                                                                 on_frame)
        writers[v].close()
        summaries.append(SequenceSummary(world_name, v, cfg.frames_per_sequence + cfg.target_frames, edit_frames,
                                         rows[v] + edit_rows, entries, pairs[v], missing))
    return summaries


def _angle_name(angle: float) -> str:
    """An angle in file names: ``15``, ``m45`` (minus), ``22p5`` (point)."""
    return format(angle, "g").replace("-", "m").replace(".", "p")


def _counterfactual_targets(cfg: SynthConfig, world: World, world_name: str, variation: str,
                            rendered: list[tuple[FrameObjects, ObjectStats, np.ndarray]]) -> list[Target]:
    """A sequence's counterfactual targets: ``cfg.counterfactual_cars`` distinct (test frame, car) pairs drawn from
    the eligible ones (:func:`~sdn3d.data.synth.counterfactual.eligible_targets`), first among those free to turn by
    every angle, then (when too few are) among the others, whose turn pairs list the cars they overlap; in frame and
    object order."""
    if cfg.counterfactual_cars == 0:
        return []
    rng = rng_for(cfg.seed, world_name, variation, "counterfactual")
    frames = range(cfg.first_test_frame, cfg.frames_per_sequence)
    free = [Target(f, i) for f in frames
            for i in eligible_targets(world, *rendered[f][:2], cfg.intrinsics, cfg.counterfactual_turns)]
    others = [Target(f, i) for f in frames for i in eligible_targets(world, *rendered[f][:2], cfg.intrinsics,
                                                                      free=False) if Target(f, i) not in free]
    picked = []
    for candidates in (free, others):
        n = min(cfg.counterfactual_cars - len(picked), len(candidates))
        if n > 0:
            picked += [candidates[int(k)] for k in rng.choice(len(candidates), size=n, replace=False)]
    return sorted(picked, key=lambda t: (t.frame, t.index))


def _counterfactual_pairs(root: Path, cfg: SynthConfig, world: World, world_name: str, variations: tuple[str, ...],
                          rendered: list[tuple[FrameObjects, ObjectStats, np.ndarray]]) -> dict[str, list[dict]]:
    """Render and write the counterfactual pairs of the ``variations`` (one camera) of a world; returns each
    variation's index entries (``docs/DATA.md``). Every target's source and counterfactual geometry is rendered
    once and lit per variation that drew it, with the source frame's own per-frame seed."""
    picks = {v: _counterfactual_targets(cfg, world, world_name, v, rendered) for v in variations}
    out: dict[str, list[dict]] = {v: [] for v in variations}
    intrinsics = cfg.intrinsics
    cars = world.cars
    for target in sorted({t for ts in picks.values() for t in ts}, key=lambda t: (t.frame, t.index)):
        objects, _, pose = rendered[target.frame]
        i = target.index
        changed = [("turn", a, turned(objects, i, a)) for a in cfg.counterfactual_turns]
        if cfg.counterfactual_delete:
            changed.append(("delete", None, deleted(objects, i)))
        source_geometry = render_geometry(world, objects, pose, intrinsics)
        geometries = [render_geometry(world, o, pose, intrinsics) for _, _, o in changed]
        instance_ids = [VKITTI_CLASS_INDEX[cars.category[t]] * 1000 + int(cars.tid[t]) + 1 for t in objects.track]
        track = int(objects.track[i])
        tid = int(cars.tid[track])
        instance_id = instance_ids[i]
        for v in (v for v in variations if target in picks[v]):
            seed = _frame_seed(cfg, world_name, v, target.frame)
            source = light_frame(source_geometry, v, seed)
            source_mask = source.instance == i
            folder = Path(PAIRS_DIR) / world_name / v / f"{target.frame:05d}_{instance_id}"
            write_staged(root / folder / "source_mask.png", mask_png_bytes(source_mask))
            for (kind, angle, _), geometry in zip(changed, geometries, strict=True):
                frame = light_frame(geometry, v, seed)
                target_mask = frame.instance == i if kind == "turn" else np.zeros_like(source_mask)
                vacated, shadow = pair_masks(source.rgb, source_mask, frame.rgb, target_mask)
                stem = "delete" if kind == "delete" else "turn_" + _angle_name(angle)
                files = {"target": f"{stem}.png", "target_mask": f"{stem}_mask.png",
                         "vacated": f"{stem}_vacated.png", "shadow": f"{stem}_shadow.png"}
                write_staged(root / folder / files["target"], png_bytes(frame.rgb))
                for key, mask in (("target_mask", target_mask), ("vacated", vacated), ("shadow", shadow)):
                    write_staged(root / folder / files[key], mask_png_bytes(mask))
                ry = float(objects.ry[i])
                out[v].append({
                    "world": world_name, "variation": v, "frame": target.frame, "instance_id": instance_id,
                    "track_id": tid, "model": str(cars.model[track]), "kind": kind, "angle_deg": angle,
                    "ry_source": ry, "ry_target": float(turned(objects, i, angle).ry[i]) if kind == "turn" else None,
                    "overlaps": ([instance_ids[j] for j in turn_overlaps(world, objects, i, angle, 0.0)]
                                 if kind == "turn" else []),
                    "from": full_resolution_centre(objects, i),
                    "source": frame_path(Path("."), "rgb", world_name, v, target.frame).as_posix(),
                    "source_mask": (folder / "source_mask.png").as_posix(),
                    **{key: (folder / name).as_posix() for key, name in files.items()},
                    "pixels": {"source_mask": int(source_mask.sum()), "target_mask": int(target_mask.sum()),
                               "vacated": int(vacated.sum()), "shadow": int(shadow.sum())},
                })
    return out


def _edit_targets(writer: SequenceWriter, cfg: SynthConfig, world: World, world_name: str, variation: str,
                  rendered: list[tuple[FrameObjects, ObjectStats, np.ndarray]],
                  on_frame: Callable[[], None] | None
                  ) -> tuple[list[BenchmarkEntry], list[int], int, list[MissingEntry]]:
    """Draw, render and write a sequence's edit targets (frames ``F .. F+E-1``, then the occluder-removed pairs');
    returns the benchmark entries, the target frame numbers, their motgt row count and the pairs that could not be
    made (written as entries without operations). A rejected edit is rendered without its lighting."""
    intrinsics = cfg.intrinsics
    first_test = cfg.first_test_frame  # edit sources come from the test part of the sequence
    entries, edit_frames, rows = [], [], 0
    missing: list[MissingEntry] = []
    for k in range(cfg.edit_pairs):
        rng = rng_for(cfg.seed, world_name, variation, "edit", k)
        source = int(rng.integers(first_test, cfg.frames_per_sequence))
        objects, stats, pose = rendered[source]
        for _ in range(_EDIT_ATTEMPTS):
            edited, operations, modified = sample_edit(
                rng, world, objects, stats, pose, intrinsics, cfg.max_edit_operations, cfg.edit_delete_share
            )
            geometry = render_geometry(world, edited, pose, intrinsics)
            # Every modified car must stay visible in the target (motgt lists visible cars only).
            if (geometry.stats.visible[modified] > 0).all():
                if not operations:
                    missing.append(MissingEntry("edit", world_name, variation, Missing.NO_EDITABLE_CAR,
                                                f"no car of source frame {source} can be edited"))
                break
        else:  # no such edit found: an entry without operations (the target re-renders the source)
            edited, operations = objects, []
            geometry = render_geometry(world, edited, pose, intrinsics)
            missing.append(MissingEntry("edit", world_name, variation, Missing.EDIT_HIDES_CAR,
                                        f"each of {_EDIT_ATTEMPTS} edits drawn on source frame {source} hid an "
                                        "edited car"))
        target = cfg.frames_per_sequence + k
        frame = light_frame(geometry, variation, _frame_seed(cfg, world_name, variation, source))
        rows += _write(writer, target, frame, pose, world, edited)
        if on_frame is not None:
            on_frame()
        edit_frames.append(target)
        entries.append(BenchmarkEntry(world_name, variation, source, target, tuple(operations)))
    refused: set[tuple[int, tuple[int, int]]] = set()  # (frame, pair) known to reveal too little: not re-rendered
    for k in range(cfg.occluder_pairs):
        target = cfg.frames_per_sequence + cfg.edit_pairs + k
        source, edited, operations, geometry, why = _occluder_removal(cfg, world, world_name, variation, rendered, k,
                                                                      refused)
        if why is not None:
            missing.append(MissingEntry("occluder_removed", world_name, variation, *why))
        frame = light_frame(geometry, variation, _frame_seed(cfg, world_name, variation, source))
        rows += _write(writer, target, frame, rendered[source][2], world, edited)
        if on_frame is not None:
            on_frame()
        edit_frames.append(target)
        entries.append(BenchmarkEntry(world_name, variation, source, target, tuple(operations),
                                      "occluder_removed" if operations else "edit"))
    return entries, edit_frames, rows, missing


#: A revealed car must gain at least this share of its source pixels for an occluder-removed pair.
_REVEAL_GAIN = 0.2


def _occluder_removal(cfg: SynthConfig, world: World, world_name: str, variation: str,
                      rendered: list[tuple[FrameObjects, ObjectStats, np.ndarray]], k: int,
                      refused: set[tuple[int, tuple[int, int]]]
                      ) -> tuple[int, FrameObjects, list, Any, tuple[Missing, str] | None]:
    """``(source frame, edited objects, operations, target geometry, None)`` of occluder-removed pair ``k``: a pair
    (:func:`~sdn3d.data.synth.edits.occluder_candidates`) of a test-part frame whose deletion reveals at least
    :data:`_REVEAL_GAIN` more of the hidden car. None such: an entry without operations on a random test frame (its
    target re-renders the source) and, last, ``(reason, why)``.

    The test frames are visited in a random order, one drawn pair each; only when every drawn pair reveals too
    little are all the other pairs of every test frame tried, in a random order (so the sequences that found a pair
    in the first pass keep it, byte for byte). ``refused``: pairs (with their frame) found to reveal too little by
    an earlier call on this sequence, added to here; they are refused again without a render.
    """
    intrinsics = cfg.intrinsics
    rng = rng_for(cfg.seed, world_name, variation, "occluder", k)
    sources = [int(f) for f in rng.permutation(np.arange(cfg.first_test_frame, cfg.frames_per_sequence))]
    tried: set[tuple[int, tuple[int, int]]] = set()

    def reveals(source: int, pair: tuple[int, int]) -> tuple[FrameObjects, list, Any] | None:
        tried.add((source, pair))
        if (source, pair) in refused:
            return None
        objects, stats, pose = rendered[source]
        edited, operations, hidden, revealed = remove_occluder(objects, *pair)
        geometry = render_geometry(world, edited, pose, intrinsics)
        if geometry.stats.visible[revealed] >= (1 + _REVEAL_GAIN) * stats.visible[hidden]:
            return edited, operations, geometry
        refused.add((source, pair))
        return None

    candidates: dict[int, OccluderCandidates] = {}
    for source in sources:
        candidates[source] = found = occluder_candidates(*rendered[source][:2], intrinsics)
        if found.pairs:
            picked = reveals(source, found.pairs[int(rng.integers(len(found.pairs)))])
            if picked is not None:
                return source, *picked, None
    others = [(f, pair) for f in sources for pair in candidates[f].pairs if (f, pair) not in tried]
    for n in rng.permutation(len(others)):
        picked = reveals(*others[int(n)])
        if picked is not None:
            return others[int(n)][0], *picked, None
    first, last = cfg.first_test_frame, cfg.frames_per_sequence - 1
    frames = f"test frames {first}-{last}" if last > first else f"test frame {first}"
    pairs = sum(len(c.pairs) for c in candidates.values())
    if pairs:
        why = (Missing.TOO_LITTLE_REVEALED, f"deleting the occluder of any of the {pairs} candidate pairs of "
               f"{frames} reveals less than {_REVEAL_GAIN:.0%} more of the hidden car")
    elif any(c.hidden for c in candidates.values()):
        why = (Missing.NO_OCCLUDER, f"the partly hidden cars of {frames} have no car in front that a point can "
               "pick (nearer, its box overlapping, its centre in the frame and 12 px from any other's)")
    else:
        why = (Missing.NO_HIDDEN_CAR, f"no partly hidden car in {frames} (at most {MAX_HIDDEN_FRACTION:.0%} "
               f"visible, >= {hidden_min_pixels(intrinsics)} pixels, truncation <= 0.3, beyond 3 m)")
    source = sources[0]
    objects, _, pose = rendered[source]
    return source, objects, [], render_geometry(world, objects, pose, intrinsics), why


def sequence_groups(jobs: Sequence[tuple[str, str]]) -> list[tuple[str, tuple[str, ...]]]:
    """``(world, variations)`` groups of ``(world, variation)`` jobs whose variations share the camera (one
    :func:`generate_sequences` call each), in the order of their first job."""
    groups: dict[tuple[str, float], list[str]] = {}
    for world, variation in jobs:
        groups.setdefault((world, CAMERA_YAW_DEG.get(variation, 0.0)), []).append(variation)
    return [(world, tuple(names)) for (world, _), names in groups.items()]


#: Where a rendering process reports its finished frames (set by :func:`_init_worker`; None: no reports).
_frames_done: Queue | None = None


def _report_frame() -> None:
    if _frames_done is not None:
        _frames_done.put(1)


def _run_group(args: tuple[str, SynthConfig, str, tuple[str, ...]]) -> list[SequenceSummary]:
    """A group of sequences in a rendering process: its frames are reported to the queue :func:`_init_worker` set."""
    return _run_group_here(args, _report_frame)


def _run_group_here(args: tuple[str, SynthConfig, str, tuple[str, ...]],
                    on_frame: Callable[[], None] | None = None) -> list[SequenceSummary]:
    root, cfg, world, variations = args
    previous = torch.get_num_threads()
    torch.set_num_threads(cfg.threads)
    try:
        return generate_sequences(Path(root), cfg, world, variations, on_frame)
    finally:  # in-process runs must not change the caller's thread count
        torch.set_num_threads(previous)


#: ``PR_SET_PDEATHSIG`` of ``<linux/prctl.h>``: the signal a process gets when its parent ends.
_PR_SET_PDEATHSIG = 1


def _die_with_parent() -> bool:
    """Ask Linux to SIGKILL this process when its parent ends; False where ``prctl`` is unavailable."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        zero = ctypes.c_ulong(0)
        return libc.prctl(_PR_SET_PDEATHSIG, ctypes.c_ulong(int(signal.SIGKILL)), zero, zero, zero) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(owner: int, parent: int, interval: float = 0.5) -> None:
    """Fallback of :func:`_die_with_parent`: end this process once ``owner`` or its parent is gone."""
    while True:
        time.sleep(interval)
        if os.getppid() != parent or not process_alive(owner):
            os._exit(1)


def _init_worker(owner: int, frames_done: Queue | None = None) -> None:
    """Initializer of the rendering processes: they end with ``owner``, the process generating the dataset,
    and put a 1 in ``frames_done`` (if given) after each frame they write.

    A killed ``sdn3d-synth`` (SIGKILL, OOM) must not leave workers rendering into a tree nobody will use.
    """
    global _frames_done
    _frames_done = frames_done
    if _die_with_parent():
        # The parent may have ended before prctl took effect: then no signal comes (with the default fork
        # start method the parent is ``owner``; with forkserver it is the server, which ends with it).
        if os.getppid() != owner and not process_alive(owner):
            os._exit(1)
        return
    threading.Thread(target=_watch_parent, args=(owner, os.getppid()), name="sdn3d-synth-parent-watch",
                     daemon=True).start()


def _flush_to_disk(tree: Path) -> None:
    """Flush the file system holding ``tree`` to disk (Linux ``syncfs``; ``os.sync`` elsewhere): one call
    for every file the sequences wrote, before the staged tree becomes the dataset."""
    if sys.platform.startswith("linux"):
        fd = os.open(tree, os.O_RDONLY)
        try:
            if ctypes.CDLL(None, use_errno=True).syncfs(fd) == 0:
                return
        except (OSError, AttributeError):
            pass
        finally:
            os.close(fd)
    os.sync()


def _in_job_order(jobs: Sequence[tuple[str, str]], groups: list[list[SequenceSummary]]) -> list[SequenceSummary]:
    by_job = {(s.world, s.variation): s for group in groups for s in group}
    return [by_job[job] for job in jobs]


def _render_all(tmp: Path, cfg: SynthConfig, jobs: list[tuple[str, str]], progress: FrameProgress | None
                ) -> list[SequenceSummary]:
    """Every sequence of ``jobs`` written under ``tmp`` (in ``jobs`` order), by groups sharing the camera
    (:func:`sequence_groups`) in ``cfg.workers`` processes; frames reported to ``progress`` as they are written
    (from the processes through a queue read by a thread of this one)."""
    args = [(str(tmp), cfg, w, vs) for w, vs in sequence_groups(jobs)]
    if cfg.workers <= 1 or len(args) <= 1:
        return _in_job_order(jobs, [_run_group_here(a, None if progress is None else progress.update) for a in args])
    context = multiprocessing.get_context()
    frames_done = context.Queue() if progress is not None else None

    def listen() -> None:
        while frames_done.get() is not None:
            progress.update()

    listener = threading.Thread(target=listen, name="sdn3d-synth-progress", daemon=True)
    if frames_done is not None:
        listener.start()
    try:
        with ProcessPoolExecutor(max_workers=min(cfg.workers, len(args)), mp_context=context,
                                 initializer=_init_worker, initargs=(os.getpid(), frames_done)) as pool:
            return _in_job_order(jobs, list(pool.map(_run_group, args)))
    finally:
        if frames_done is not None:
            frames_done.put(None)  # after every worker's reports (the pool has shut down)
            listener.join(timeout=5.0)


def generate_dataset(cfg: SynthConfig, sequences: Sequence[tuple[str, str]] | None = None,
                     progress: bool | TextIO = False) -> Path:
    """Generate the dataset described by ``cfg``; returns the output directory.

    Args:
        cfg: the configuration.
        sequences: optional ``(world, variation)`` subset (default: every world x variation).
        progress: report finished frames, frames/s and the ETA (:class:`~sdn3d.data.synth.progress.FrameProgress`)
            on stderr (True) or on the given stream; one line updated in place on a terminal, a line every
            30 s elsewhere. Frames are counted as each is written, whichever process renders it.

    Raises:
        sdn3d.io.OutputDirError (a UserInputError and FileExistsError): ``output_dir`` may not be written:
            it is not a directory, or a non-empty one while ``overwrite`` is false or that holds no
            ``synth_manifest.json`` (not an earlier dataset), or the working directory, the home
            directory, one of their parents or ``/``. Checked before anything is rendered.
    """
    out = Path(cfg.output_dir).expanduser().resolve()
    jobs = list(sequences) if sequences is not None else [(w, v) for w in cfg.worlds for v in cfg.variations]
    with staged_directory(out, MANIFEST_NAME, cfg.overwrite, owned=True) as tmp:
        reporter = None
        if progress is not False:
            total = len(jobs) * (cfg.frames_per_sequence + cfg.target_frames)
            reporter = FrameProgress(total, None if progress is True else progress)
        try:
            summaries = _render_all(tmp, cfg, jobs, reporter)
        finally:
            if reporter is not None:
                reporter.close()
        entries = [e for s in summaries for e in s.entries]
        save_edit_benchmark(entries, tmp / BENCHMARK_NAME)
        recorded = cfg.recorded()
        counts = manifest_counts(entries, [m for s in summaries for m in s.missing], len(summaries), recorded)
        intrinsics = cfg.intrinsics
        extra = {}
        if cfg.counterfactual_cars:
            write_json_atomic(tmp / PAIRS_NAME, {
                "format": PAIRS_FORMAT,
                "version": 1,
                "image_size": list(cfg.image_size),
                "shadow_threshold": SHADOW_THRESHOLD,
                "angle": "degrees added to the target's yaw ry (KITTI: about the camera's y axis, which points down)",
                "from_coordinates": "pixels of the 1242x375 frame",
                "pairs": [p for s in summaries for p in s.counterfactual],
            })
            extra["counterfactual_pairs"] = PAIRS_NAME
        write_json_atomic(
            tmp / MANIFEST_NAME,
            {
                "format": "Virtual KITTI 1.3.1 (synthetic, sdn3d)",
                "config": recorded,
                **extra,
                "intrinsics": intrinsics.to_dict(),
                "intrinsics_note": ("VKITTI_INTRINSICS (1242x375, fx=fy=725, cx=620.5, cy=187) resized to image_size"),
                "benchmark": BENCHMARK_NAME,
                "benchmark_coordinates": "pixels of the 1242x375 frame",
                MANIFEST_KEY: counts_json(counts),
                "sequences": [
                    {
                        "world": s.world,
                        "variation": s.variation,
                        "frames": s.frames,
                        "edit_target_frames": s.edit_frames,
                        "object_rows": s.object_rows,
                    }
                    for s in summaries
                ],
            },
        )
        write_class_statistics(tmp)  # class_stats.STATISTICS_NAME, read from the written scenegt files
        _flush_to_disk(tmp)  # the sequences' files were written without fsync (writer.write_staged)
        write_text_atomic(tmp / "_SUCCESS", "")
    for line in shortfall_lines(counts, "sdn3d-synth"):  # a kind short of entries is scored on fewer, or none
        print(line, file=sys.stderr)
    return out
