# ruff: noqa: E402
"""Each cut of this branch against the code it replaced, in one process, at threads 1, on the latency tree's inputs
(benchmarks/photo_latency.py's tree: 1242x375, worlds 0001 and 0018, ground-truth geometry (oracle)):

- ``_dark_car_tyres``: every car of each source frame's ``PhotoSource`` (the registered tyres of ``render_photo``);
- ``_trace``: the rays of the removal fill of the latency edits' frames, as ``ray_fill`` traces them (a hole of the
  frame's largest car, the vanishing point from the camera).

Each call is timed ``--rounds`` times, new code then main's, the least kept; each pair's results are compared for
equality.

    python micro.py TREE BASE_SRC [--rounds 7]
"""

import argparse
import importlib.util
import os
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np
import torch

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo import road, transfer

parser = argparse.ArgumentParser()
parser.add_argument("tree", type=Path)
parser.add_argument("base_src", type=Path)
parser.add_argument("--rounds", type=int, default=7)
args = parser.parse_args()
torch.set_num_threads(1)


def load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


base_transfer = load("base_transfer", args.base_src / "sdn3d/editing/photo/transfer.py")
base_road = load("base_road", args.base_src / "sdn3d/editing/photo/road.py")
records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(args.tree)}
keys = sorted({(e.world, e.variation, e.source_frame)
               for e in load_edit_benchmark(args.tree / BENCHMARK_NAME) if e.operations})
work = (624, 192)


def least(fn, rounds):
    best, out = float("inf"), None
    for _ in range(rounds):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return 1000 * best, out


def same(a, b) -> bool:
    if a is None or b is None:
        return a is None and b is None
    if isinstance(a, tuple):
        return all(same(x, y) for x, y in zip(a, b, strict=True))
    return torch.equal(a, b)


print(f"load {os.getloadavg()[0]:.1f}; {len(keys)} source frames; least of {args.rounds}, threads 1")
totals = {"tyres": [0.0, 0.0], "trace": [0.0, 0.0]}
for key in keys:
    record = records[key]
    scene = scene_from_frame(record, work)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    frame = PixelFrame(tuple(int(x) for x in original.shape[2:0:-1]), work)
    source = transfer.PhotoSource(original.float() / 255, frame, scene)
    ids = [int(i) for i in source.src_ids.unique().tolist() if i]
    new_ms = old_ms = 0.0
    equal = True
    for iid in ids:
        args_of = (source.image, source.src_ids, source.parts, iid)
        t_new, a = least(partial(transfer._dark_car_tyres, *args_of), args.rounds)
        t_old, b = least(partial(base_transfer._dark_car_tyres, *args_of), args.rounds)
        new_ms, old_ms, equal = new_ms + t_new, old_ms + t_old, equal and same(a, b)
    totals["tyres"][0] += new_ms
    totals["tyres"][1] += old_ms
    print(f"{key}: _dark_car_tyres of {len(ids)} cars: new {new_ms:.1f} ms, main {old_ms:.1f} ms, equal {equal}")
    # the fill's trace: the hole of the frame's largest car, rays from the camera's vanishing point
    counts = torch.bincount(source.src_ids.view(-1))
    counts[0] = 0
    hole = source.src_ids == int(counts.argmax())
    valid = ~hole
    ys, xs = hole.nonzero(as_tuple=True)
    pix = torch.stack([xs, ys], 1).float()
    vp = torch.tensor([float(source.K[0, 2]), float(source.K[1, 2])], dtype=torch.float32)
    away = pix - vp
    reach = away.norm(dim=1)
    unit = torch.where(reach[:, None] > 1.0, away / reach.clamp(min=1e-6)[:, None], torch.tensor([1.0, 0.0]))
    far = min(400, int(np.hypot(float(ys.max() - ys.min()), float(xs.max() - xs.min()))) + 64)
    steps = torch.cat([torch.arange(1, 17), torch.arange(17, far + 1, 2)]).float()
    limit = (reach - 1.0).clamp(min=0)
    t_new = t_old = 0.0
    equal = True
    for u, lim in ((unit, None), (-unit, limit)):
        ta, a = least(partial(road._trace, pix, u, valid, steps, lim), args.rounds)
        tb, b = least(partial(base_road._trace, pix, u, valid, steps, lim), args.rounds)
        t_new, t_old, equal = t_new + ta, t_old + tb, equal and same(a, b)
    totals["trace"][0] += t_new
    totals["trace"][1] += t_old
    print(f"{key}: _trace both ways of {len(pix)} rays: new {t_new:.1f} ms, main {t_old:.1f} ms, equal {equal}")
for name, (n, o) in totals.items():
    print(f"sum {name}: new {n:.1f} ms, main {o:.1f} ms ({n / o:.3f})")
print(f"load {os.getloadavg()[0]:.1f}")
