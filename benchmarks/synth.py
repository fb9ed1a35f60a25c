"""Benchmark of the synthetic Virtual KITTI generator: frames per second, printed as JSON.

Two figures, each the median over ``--runs`` runs:

- ``render_fps``: :func:`render_frame` alone (scene assembly, rasterization, texturing, object
  statistics) on the frames of one sequence;
- ``generate_fps``: :func:`generate_dataset` end to end (also the world sampling, PNG / text
  writing and the final rename), ``--sequences`` sequences of ``--frames`` frames each, run with
  ``--workers`` processes.

``--profile`` adds the top functions by cumulative time of one render pass. The load average is
reported because the machine may be shared (timings then vary a lot).

Usage: ``.venv/bin/python benchmarks/synth.py --frames 20 --runs 3 --threads 1 --workers 1``
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20, help="frames per sequence")
    parser.add_argument("--sequences", type=int, default=2, help="sequences for generate_fps")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--width", type=int, default=624)
    parser.add_argument("--height", type=int, default=192)
    parser.add_argument("--threads", type=int, default=1, help="torch threads per process")
    parser.add_argument("--workers", type=int, default=1, help="processes for generate_dataset")
    parser.add_argument("--world", default="0001")
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    variations = tuple(VARIATIONS[: max(1, args.sequences)])
    with tempfile.TemporaryDirectory(prefix="sdn3d-synth-bench-") as tmp:
        cfg = SynthConfig(
            output_dir=str(Path(tmp) / "data"),
            seed=0,
            image_size=(args.width, args.height),
            worlds=(args.world,),
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
        generate = []
        for _ in range(args.runs):
            start = time.perf_counter()
            generate_dataset(cfg)
            generate.append(args.frames * len(variations) / (time.perf_counter() - start))
        result = {
            "image_size": [args.width, args.height],
            "frames_per_run": {"render": args.frames, "generate": args.frames * len(variations)},
            "runs": args.runs,
            "render_fps": round(statistics.median(render), 3),
            "generate_fps": round(statistics.median(generate), 3),
            "render_fps_all": [round(v, 3) for v in render],
            "generate_fps_all": [round(v, 3) for v in generate],
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
