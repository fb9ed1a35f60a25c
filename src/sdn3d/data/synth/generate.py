"""Generate a synthetic dataset in the Virtual KITTI 1.3.1 format (the project's embedded data).

:func:`generate_dataset` renders every ``<world>/<variation>`` sequence of a
:class:`SynthConfig` and writes the Virtual KITTI 1.3.1 tree (see ``writer.py``), the editing
benchmark ``vkitti_edit_benchmark.json`` (3D-SDN format, see ``edits.py``) and
``synth_manifest.json``. Edit targets are frames of their own sequence numbered after the
regular frames: a sequence of ``F`` frames and ``E`` edit pairs holds frames ``0 .. F-1``
(the camera drives on) and ``F .. F+E-1`` (edited copies of a source frame, same camera).

The write is all-or-nothing: everything goes to a temporary sibling directory that is renamed
onto ``output_dir`` at the end (after ``_SUCCESS`` is written in it; :func:`sdn3d.io.staged_directory`).
An existing non-empty ``output_dir`` is refused unless ``overwrite``, and even then unless it is an earlier
dataset of this generator (it holds ``synth_manifest.json``); it is then replaced only once the new tree
is complete. The working directory, the home directory, their parents and ``/`` are never replaced.
While it is written the temporary tree holds an owner record (this process and host): a run that was
killed (SIGKILL, OOM) leaves it behind, and the next run into the same ``output_dir`` removes it.
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
import numbers
import os
import signal
import sys
import threading
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch

from sdn3d.data.edit_benchmark import BenchmarkEntry, save_edit_benchmark
from sdn3d.data.synth.edits import sample_edit
from sdn3d.data.synth.layout import (
    CAMERA_YAW_DEG,
    VARIATIONS,
    FrameObjects,
    World,
    build_world,
    frame_objects,
    rng_for,
)
from sdn3d.data.synth.scene_render import RenderedFrame, render_frame
from sdn3d.data.synth.stats import ObjectStats
from sdn3d.data.synth.writer import SequenceWriter
from sdn3d.errors import UserInputError
from sdn3d.io import process_alive, staged_directory, write_json_atomic, write_text_atomic
from sdn3d.math3d.camera import VKITTI_INTRINSICS, Intrinsics

__all__ = [
    "SynthConfig",
    "SynthConfigError",
    "generate_dataset",
    "generate_sequence",
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
        max_edit_operations: at most this many operations per pair.
        overwrite: replace a non-empty ``output_dir``.
        workers: processes rendering sequences in parallel (1: in this process).
        threads: torch threads per process.
    """

    output_dir: str
    seed: int = 0
    image_size: tuple[int, int] = (624, 192)
    worlds: tuple[str, ...] = ("0001",)
    variations: tuple[str, ...] = ("clone",)
    frames_per_sequence: int = 10
    cars_per_frame: tuple[int, int] = (4, 12)
    edit_pairs: int = 2
    max_edit_operations: int = 3
    overwrite: bool = False
    workers: int = 1
    threads: int = 1

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
        put("max_edit_operations", _integer("max_edit_operations", self.max_edit_operations, 1))
        if self.frames_per_sequence + self.edit_pairs > 99999:
            raise SynthConfigError("frames_per_sequence + edit_pairs must fit 5-digit frame numbers (<= 99999)")
        if not isinstance(self.overwrite, (bool, np.bool_)):
            raise SynthConfigError(f"overwrite must be true or false, got {_got(self.overwrite)}")
        put("overwrite", bool(self.overwrite))
        put("workers", _integer("workers", self.workers, 1))
        put("threads", _integer("threads", self.threads, 1))

    @property
    def intrinsics(self) -> Intrinsics:
        width, height = self.image_size
        return VKITTI_INTRINSICS.resized(width, height)

    def to_dict(self) -> dict:
        out = asdict(self)
        return {k: list(v) if isinstance(v, tuple) else v for k, v in out.items()}


@dataclass
class SequenceSummary:
    """What one sequence wrote: frame and object-row counts and its benchmark entries."""

    world: str
    variation: str
    frames: int
    edit_frames: list[int]
    object_rows: int
    entries: list[BenchmarkEntry]


@functools.lru_cache(maxsize=4)
def _world(seed: int, name: str, frames: int, cars: tuple[int, int]) -> World:
    return build_world(seed, name, frames, cars)


def _annotations(world: World, objects: FrameObjects, frame: RenderedFrame) -> dict[str, np.ndarray]:
    cars = world.cars
    dims = cars.dims[objects.track]
    bottom = objects.center + np.stack([np.zeros(len(objects)), dims[:, 1] / 2, np.zeros(len(objects))], 1)
    return {
        "tid": cars.tid[objects.track],
        "dims": dims,
        "bottom": bottom,
        "ry": objects.ry,
        "box": frame.stats.box,
        "truncr": frame.stats.truncr,
        "occupr": frame.stats.occupr,
        "visible": frame.stats.visible,
        "moving": objects.moving,
        "model": np.array(cars.model, dtype=object)[objects.track] if len(cars) else np.zeros(0, object),
        "color": np.array(cars.color_name, dtype=object)[objects.track] if len(cars) else np.zeros(0, object),
        "category": np.array(cars.category, dtype=object)[objects.track] if len(cars) else np.zeros(0, object),
    }


def _frame_seed(cfg: SynthConfig, world: str, variation: str, frame: int) -> int:
    return int(rng_for(cfg.seed, world, variation, "frame", frame).integers(0, 2**31 - 1))


def generate_sequence(root: Path, cfg: SynthConfig, world_name: str, variation: str) -> SequenceSummary:
    """Render and write one ``<world>/<variation>`` sequence (regular frames, then edit targets)."""
    world = _world(cfg.seed, world_name, cfg.frames_per_sequence, cfg.cars_per_frame)
    yaw = CAMERA_YAW_DEG.get(variation, 0.0)
    intrinsics = cfg.intrinsics
    writer = SequenceWriter(
        Path(root),
        world_name,
        variation,
        world.cars.tid,
        world.cars.category,
        color_seed=int(rng_for(cfg.seed, "colors", world_name).integers(0, 2**31 - 1)),
    )
    rendered: list[tuple[FrameObjects, ObjectStats, np.ndarray]] = []
    rows = 0
    for f in range(cfg.frames_per_sequence):
        objects = frame_objects(world, f, yaw)
        pose = world.camera.pose(f, yaw)
        frame = render_frame(world, objects, pose, intrinsics, variation, _frame_seed(cfg, world_name, variation, f))
        writer.write_frame(
            f,
            frame.rgb,
            frame.class_map,
            frame.instance,
            frame.depth,
            pose,
            _annotations(world, objects, frame),
        )
        rows += int((frame.stats.visible > 0).sum())
        # Keep only what edit sampling needs (objects and statistics), not the images.
        rendered.append((objects, frame.stats, pose))
    # Edit sources come from the test part of the sequence: the last 20% (sdn3d.data.splits.paper_split, first=True).
    first_test = min(math.floor(0.8 * cfg.frames_per_sequence + 1e-9), cfg.frames_per_sequence - 1)
    entries, edit_frames = [], []
    for k in range(cfg.edit_pairs):
        rng = rng_for(cfg.seed, world_name, variation, "edit", k)
        source = int(rng.integers(first_test, cfg.frames_per_sequence))
        objects, stats, pose = rendered[source]
        frame_seed = _frame_seed(cfg, world_name, variation, source)
        for _ in range(_EDIT_ATTEMPTS):
            edited, operations, modified = sample_edit(
                rng, world, objects, stats, pose, intrinsics, cfg.max_edit_operations
            )
            frame = render_frame(world, edited, pose, intrinsics, variation, frame_seed)
            # Every modified car must stay visible in the target (motgt lists visible cars only).
            if (frame.stats.visible[modified] > 0).all():
                break
        else:  # no such edit found: an entry without operations (the target re-renders the source)
            edited, operations = objects, []
            frame = render_frame(world, edited, pose, intrinsics, variation, frame_seed)
        target = cfg.frames_per_sequence + k
        writer.write_frame(
            target,
            frame.rgb,
            frame.class_map,
            frame.instance,
            frame.depth,
            pose,
            _annotations(world, edited, frame),
        )
        rows += int((frame.stats.visible > 0).sum())
        edit_frames.append(target)
        entries.append(BenchmarkEntry(world_name, variation, source, target, tuple(operations)))
    writer.close()
    return SequenceSummary(world_name, variation, cfg.frames_per_sequence + cfg.edit_pairs, edit_frames, rows, entries)


def _run_sequence(args: tuple[str, SynthConfig, str, str]) -> SequenceSummary:
    root, cfg, world, variation = args
    previous = torch.get_num_threads()
    torch.set_num_threads(cfg.threads)
    try:
        return generate_sequence(Path(root), cfg, world, variation)
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


def _init_worker(owner: int) -> None:
    """Initializer of the rendering processes: they end with ``owner``, the process generating the dataset.

    A killed ``sdn3d-synth`` (SIGKILL, OOM) must not leave workers rendering into a tree nobody will use.
    """
    if _die_with_parent():
        # The parent may have ended before prctl took effect: then no signal comes (with the default fork
        # start method the parent is ``owner``; with forkserver it is the server, which ends with it).
        if os.getppid() != owner and not process_alive(owner):
            os._exit(1)
        return
    threading.Thread(target=_watch_parent, args=(owner, os.getppid()), name="sdn3d-synth-parent-watch",
                     daemon=True).start()


def generate_dataset(cfg: SynthConfig, sequences: Sequence[tuple[str, str]] | None = None) -> Path:
    """Generate the dataset described by ``cfg``; returns the output directory.

    Args:
        cfg: the configuration.
        sequences: optional ``(world, variation)`` subset (default: every world x variation).

    Raises:
        sdn3d.io.OutputDirError (a UserInputError and FileExistsError): ``output_dir`` may not be written:
            it is not a directory, or a non-empty one while ``overwrite`` is false or that holds no
            ``synth_manifest.json`` (not an earlier dataset), or the working directory, the home
            directory, one of their parents or ``/``. Checked before anything is rendered.
    """
    out = Path(cfg.output_dir).expanduser().resolve()
    jobs = list(sequences) if sequences is not None else [(w, v) for w in cfg.worlds for v in cfg.variations]
    with staged_directory(out, MANIFEST_NAME, cfg.overwrite, owned=True) as tmp:
        args = [(str(tmp), cfg, w, v) for w, v in jobs]
        if cfg.workers > 1 and len(jobs) > 1:
            with ProcessPoolExecutor(max_workers=min(cfg.workers, len(jobs)), initializer=_init_worker,
                                     initargs=(os.getpid(),)) as pool:
                summaries = list(pool.map(_run_sequence, args))
        else:
            summaries = [_run_sequence(a) for a in args]
        entries = [e for s in summaries for e in s.entries]
        save_edit_benchmark(entries, tmp / BENCHMARK_NAME)
        intrinsics = cfg.intrinsics
        write_json_atomic(
            tmp / MANIFEST_NAME,
            {
                "format": "Virtual KITTI 1.3.1 (synthetic, sdn3d)",
                "config": {
                    k: v for k, v in cfg.to_dict().items() if k not in ("output_dir", "overwrite", "workers", "threads")
                },
                "intrinsics": intrinsics.to_dict(),
                "intrinsics_note": ("VKITTI_INTRINSICS (1242x375, fx=fy=725, cx=620.5, cy=187) resized to image_size"),
                "benchmark": BENCHMARK_NAME,
                "benchmark_coordinates": "pixels of the 1242x375 frame",
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
        write_text_atomic(tmp / "_SUCCESS", "")
    return out
