# ruff: noqa: E402
"""Draw the 14 edits of benchmarks/photo_latency.py's tree (fill=rays, a fresh source state per edit, as the
benchmark) with the code on PYTHONPATH; write every edit's image, source and parts maps to OUT.npz (byte-identity
checks between codes) and, with --profile, a cProfile of the draws to OUT.prof.

    python draw_edits.py TREE OUT [--profile] [--reuse-source]
"""

import argparse
import cProfile
import time
from pathlib import Path

import numpy as np
import torch

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.apply import apply_edits, ops_from_benchmark
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation.edit_benchmark import edit_kind

parser = argparse.ArgumentParser()
parser.add_argument("tree", type=Path)
parser.add_argument("out", type=Path)
parser.add_argument("--profile", action="store_true")
parser.add_argument("--reuse-source", action="store_true")
parser.add_argument("--threads", type=int, default=1)
parser.add_argument("--only", default="", help="comma-separated edit indices to draw (default: all)")
args = parser.parse_args()
torch.set_num_threads(args.threads)
records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(args.tree)}
entries = [e for e in load_edit_benchmark(args.tree / BENCHMARK_NAME) if e.operations][:40]
work = (624, 192)
cases = []
for entry in entries:
    record = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(record, work)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
    cases.append((scene, edited, original, (entry.world, entry.source_frame), edit_kind(entry)))
frame = PixelFrame(tuple(int(x) for x in cases[0][2].shape[2:0:-1]), work)
renderer = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
renderer.draw(renderer.prepare(cases[0][2], frame, cases[0][0]), cases[0][1])  # warm-up
arrays = {}
states = {}
profile = cProfile.Profile() if args.profile else None
t0, c0 = time.perf_counter(), time.process_time()
only = {int(i) for i in args.only.split(",") if i}
for i, (scene, edited, original, key, kind) in enumerate(cases):
    if only and i not in only:
        continue
    e0, w0 = time.process_time(), time.perf_counter()
    if profile is not None:
        profile.enable()
    state = states.get(key) if args.reuse_source else None
    if state is None:
        state = states[key] = renderer.prepare(original, frame, scene)
    drawn = renderer.draw(state, edited)
    cpu_ms, wall_ms = 1000 * (time.process_time() - e0), 1000 * (time.perf_counter() - w0)
    print(f"edit {i} {kind}: CPU {cpu_ms:.1f} ms wall {wall_ms:.1f} ms")
    if profile is not None:
        profile.disable()
    arrays[f"image{i}"] = drawn.image.numpy()
    arrays[f"source{i}"] = drawn.photo.source.numpy()
    if drawn.photo.parts is not None:
        arrays[f"parts{i}"] = drawn.photo.parts.numpy()
print(f"{len(cases)} edits: wall {time.perf_counter() - t0:.2f} s, CPU {time.process_time() - c0:.2f} s")
np.savez_compressed(args.out.with_suffix(".npz"), **arrays)
if profile is not None:
    profile.dump_stats(str(args.out.with_suffix(".prof")))
