# ruff: noqa: E402
"""Each cut of this branch against the code it replaced, on the calls the 14 latency edits make (session14/cost/
draw_edits.py's edits of benchmarks/photo_latency.py's tree: 1242x375, ground-truth geometry (oracle), fill=rays, a
fresh source per edit), in one process at threads 1: ``transfer._dark_car_tyres``, ``transfer._grow`` and
``road._trace`` are wrapped; each call runs this branch's function and main's (BASE_SRC's module, loaded beside
it) ``--rounds`` times each, alternating, the least kept, and their results are compared for equality.

    python micro.py TREE BASE_SRC [--rounds 5]
"""

import argparse
import importlib.util
import os
import sys
import time
from collections import defaultdict
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
from sdn3d.editing.photo import road, transfer
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation.edit_benchmark import edit_kind

parser = argparse.ArgumentParser()
parser.add_argument("tree", type=Path)
parser.add_argument("base_src", type=Path)
parser.add_argument("--rounds", type=int, default=5)
args = parser.parse_args()
torch.set_num_threads(1)


def load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


base = {"_dark_car_tyres": load("base_transfer", args.base_src / "sdn3d/editing/photo/transfer.py")._dark_car_tyres,
        "_trace": load("base_road", args.base_src / "sdn3d/editing/photo/road.py")._trace}
base["_grow"] = sys.modules["base_transfer"]._grow


def same(a, b) -> bool:
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, torch.Tensor):
        return isinstance(b, torch.Tensor) and torch.equal(a, b)
    return a == b


def copies(a):  # _grow's own map is replaced, not written; copied all the same for each call
    return tuple(x.clone() if isinstance(x, torch.Tensor) else x for x in a)


times: dict[str, list[float]] = defaultdict(lambda: [0.0, 0.0, 0])
unequal: list[str] = []


def wrapped(name: str, new_fn):
    def call(*a, **k):
        best = [float("inf"), float("inf")]
        for _ in range(args.rounds):
            for i, fn in enumerate((new_fn, base[name])):
                inputs = copies(a)
                t0 = time.process_time()
                out = fn(*inputs, **k)
                best[i] = min(best[i], time.process_time() - t0)
                if i == 0:
                    got = out
                else:
                    want = out
        if not same(got, want):
            unequal.append(name)
        times[name][0] += 1000 * best[0]
        times[name][1] += 1000 * best[1]
        times[name][2] += 1
        return got
    return call


transfer._dark_car_tyres = wrapped("_dark_car_tyres", transfer._dark_car_tyres)
transfer._grow = wrapped("_grow", transfer._grow)
road._trace = wrapped("_trace", road._trace)

records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(args.tree)}
entries = [e for e in load_edit_benchmark(args.tree / BENCHMARK_NAME) if e.operations][:40]
work = (624, 192)
renderer = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
print(f"load {os.getloadavg()[0]:.1f}; least of {args.rounds} per call, threads 1; ms per edit, this branch vs main")
for n, entry in enumerate(entries):
    record = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(record, work)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
    frame = PixelFrame(tuple(int(x) for x in original.shape[2:0:-1]), work)
    before = {k: list(v) for k, v in times.items()}
    renderer.draw(renderer.prepare(original, frame, scene), edited)
    cells = [f"{k} {times[k][0] - before.get(k, [0, 0])[0]:.1f} vs {times[k][1] - before.get(k, [0, 0])[1]:.1f}"
             for k in sorted(times)]
    print(f"edit {n} {edit_kind(entry)}: " + "; ".join(cells))
for k in sorted(times):
    new_ms, old_ms, calls = times[k]
    print(f"all 14 edits, {k} ({calls} calls): {new_ms:.1f} vs {old_ms:.1f} ms ({new_ms / old_ms:.3f}); "
          f"per edit {new_ms / len(entries):.1f} vs {old_ms / len(entries):.1f} ms")
print(f"results unequal: {unequal or 'none'}; load {os.getloadavg()[0]:.1f}")
