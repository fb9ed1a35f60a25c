"""Benchmark of the synthetic Virtual KITTI generator: frames per second, printed as JSON.

Two figures, each the median over ``--runs`` runs:

- ``render_fps``: :func:`render_frame` alone (scene assembly, rasterization, texturing, object
  statistics) on the frames of one sequence;
- ``generate_fps``: :func:`generate_dataset` end to end (also the world sampling, PNG / text
  writing, the class statistics and the final rename): ``--worlds`` x ``--variations`` sequences of
  ``--frames`` frames each (default: two worlds and all ten variations, the mix of the Virtual KITTI
  release, where six variations share each frame's camera and so its geometry), run with ``--workers``
  processes of ``--threads`` torch threads.

``--profile`` adds the top functions by cumulative time of one render pass. The load average is
reported because the machine may be shared (timings then vary a lot); so is ``generate_cpu_s_per_frame``, the
CPU seconds per frame of ``generate_dataset`` (this process and its rendering processes, ``getrusage``), which
a busy machine inflates much less than wall time: ``cores / generate_cpu_s_per_frame`` is what ``cores`` idle
cores would reach if the work spread evenly over them.

Usage: ``.venv/bin/python benchmarks/synth.py --frames 4 --runs 3 --threads 1 --workers 2``
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
import resource
import statistics
import tempfile
import time
from pathlib import Path

import torch

from sdn3d.data.synth import SynthConfig, build_world, frame_objects, generate_dataset, render_frame
from sdn3d.data.synth.layout import CAMERA_YAW_DEG, VARIATIONS


def _render_pass(cfg: SynthConfig, world: str, variation: str) -> float:
    w = build_world(cfg.seed, world, cfg.frames_per_sequence, cfg.cars_per_frame)
    yaw = CAMERA_YAW_DEG.get(variation, 0.0)
    start = time.perf_counter()
    for f in range(cfg.frames_per_sequence):
        render_frame(w, frame_objects(w, f, yaw), w.camera.pose(f, yaw), cfg.intrinsics, variation, f)
    return time.perf_counter() - start


def _cpu_seconds() -> float:
    """CPU seconds (user + system) of this process and of its ended child processes (the rendering workers)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20, help="frames per sequence")
    parser.add_argument("--worlds", nargs="+", default=["0001", "0002"], help="worlds for generate_fps")
    parser.add_argument("--variations", nargs="+", default=list(VARIATIONS), help="variations for generate_fps")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--width", type=int, default=624)
    parser.add_argument("--height", type=int, default=192)
    parser.add_argument("--threads", type=int, default=1, help="torch threads per process")
    parser.add_argument("--workers", type=int, default=1, help="processes for generate_dataset")
    parser.add_argument("--world", default="0001", help="world of render_fps (clone)")
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    variations = tuple(args.variations)
    with tempfile.TemporaryDirectory(prefix="sdn3d-synth-bench-") as tmp:
        cfg = SynthConfig(
            output_dir=str(Path(tmp) / "data"),
            seed=0,
            image_size=(args.width, args.height),
            worlds=tuple(args.worlds),
            variations=variations,
            frames_per_sequence=args.frames,
            cars_per_frame=(6, 14),
            edit_pairs=0,
            overwrite=True,
            workers=args.workers,
            threads=args.threads,
        )
        _render_pass(SynthConfig(**{**cfg.to_dict(), "frames_per_sequence": 2}), args.world, "clone")  # warm-up
        load_before = os.getloadavg()
        render = [args.frames / _render_pass(cfg, args.world, "clone") for _ in range(args.runs)]
        generate, cpu = [], []
        frames = args.frames * len(variations) * len(args.worlds)
        for _ in range(args.runs):
            cpu_start = _cpu_seconds()
            start = time.perf_counter()
            generate_dataset(cfg)
            generate.append(frames / (time.perf_counter() - start))
            cpu.append((_cpu_seconds() - cpu_start) / frames)
        result = {
            "image_size": [args.width, args.height],
            "frames_per_run": {"render": args.frames, "generate": frames},
            "runs": args.runs,
            "render_fps": round(statistics.median(render), 3),
            "generate_fps": round(statistics.median(generate), 3),
            "render_fps_all": [round(v, 3) for v in render],
            "generate_fps_all": [round(v, 3) for v in generate],
            "generate_cpu_s_per_frame": round(statistics.median(cpu), 4),
            "torch_threads": torch.get_num_threads(),
            "workers": args.workers,
            "cpu_count": os.cpu_count(),
            "loadavg_before": [round(v, 2) for v in load_before],
            "loadavg_after": [round(v, 2) for v in os.getloadavg()],
        }
        if args.profile:
            profiler = cProfile.Profile()
            profiler.enable()
            _render_pass(cfg, args.world, "clone")
            profiler.disable()
            stream = io.StringIO()
            pstats.Stats(profiler, stream=stream).sort_stats("cumulative").print_stats(18)
            result["profile"] = stream.getvalue().splitlines()
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
