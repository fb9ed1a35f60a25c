# ruff: noqa: E402, E501
"""The 14 latency edits (session14/cost/draw_edits.py's cases: 1242x375, ground-truth geometry (oracle), fill=rays, a
fresh source per edit, ``renderer.prepare`` + ``draw``) drawn both ways in one process at threads 1: with this
branch's code, and with main's photo transfer, rasterizer and normal map (BASE_SRC's ``editing/photo/transfer.py``,
``render/rasterize.py`` and ``render/maps.py`` loaded beside this branch's and swapped in: every module this branch
changed on the photo path; ``math3d/sums.py`` is new). The arms alternate edit by edit, A-B, then B-A in the next
round; per edit the least CPU time over ``--rounds`` is kept, then paired: geometric mean of new/main with a paired
bootstrap 95 % interval (10k resamples of the edits) and wins / losses. The two arms' pictures are compared.

    python ab.py TREE BASE_SRC [--rounds 3]
"""

import argparse
import importlib.util
import os
import sys
import time
from pathlib import Path

import numpy as np
import torch

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing import appearance
from sdn3d.editing.apply import apply_edits, ops_from_benchmark
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo import transfer
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation.edit_benchmark import edit_kind
from sdn3d.scene import maps as scene_maps

parser = argparse.ArgumentParser()
parser.add_argument("tree", type=Path)
parser.add_argument("base_src", type=Path)
parser.add_argument("--rounds", type=int, default=3)
args = parser.parse_args()
torch.set_num_threads(1)


def load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


base_raster = load("base_rasterize", args.base_src / "sdn3d/render/rasterize.py")
base_maps = load("base_render_maps", args.base_src / "sdn3d/render/maps.py")
base_maps.rasterize_meshes = base_raster.rasterize_meshes
base_transfer = load("base_transfer", args.base_src / "sdn3d/editing/photo/transfer.py")
base_transfer.rasterize_meshes, base_transfer.normal_map = base_raster.rasterize_meshes, base_maps.normal_map
arms = {"new": (transfer.PhotoSource, transfer.render_photo, scene_maps.rasterize_meshes),
        "main": (base_transfer.PhotoSource, base_transfer.render_photo, base_raster.rasterize_meshes)}


def use(arm: str) -> None:
    appearance.PhotoSource, appearance.render_photo, scene_maps.rasterize_meshes = arms[arm]


records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(args.tree)}
entries = [e for e in load_edit_benchmark(args.tree / BENCHMARK_NAME) if e.operations][:40]
work = (624, 192)
cases = []
for entry in entries:
    record = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(record, work)
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record))).permute(2, 0, 1)
    edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
    cases.append((scene, edited, original, edit_kind(entry)))
frame = PixelFrame(tuple(int(x) for x in cases[0][2].shape[2:0:-1]), work)
renderer = appearance.appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
for arm in arms:  # warm-up
    use(arm)
    renderer.draw(renderer.prepare(cases[0][2], frame, cases[0][0]), cases[0][1])
loads = [os.getloadavg()[0]]
best = {arm: np.full(len(cases), np.inf) for arm in arms}
pictures: dict[str, list] = {arm: [None] * len(cases) for arm in arms}
for r in range(args.rounds):
    for i, (scene, edited, original, _) in enumerate(cases):
        for arm in (("new", "main") if (r + i) % 2 == 0 else ("main", "new")):
            use(arm)
            c0 = time.process_time()
            drawn = renderer.draw(renderer.prepare(original, frame, scene), edited)
            best[arm][i] = min(best[arm][i], 1000 * (time.process_time() - c0))
            pictures[arm][i] = (drawn.image, drawn.photo.source, drawn.photo.parts)
    loads.append(os.getloadavg()[0])
same = all(all(torch.equal(a, b) for a, b in zip(x, y, strict=True))
           for x, y in zip(pictures["new"], pictures["main"], strict=True))
ratio = best["new"] / best["main"]
rng = np.random.default_rng(0)
boot = np.exp(np.log(ratio)[rng.integers(0, len(ratio), (10000, len(ratio)))].mean(1))
print(f"14 latency edits, least CPU of {args.rounds} rounds per edit and arm, threads 1, load (1 min) "
      f"{min(loads):.1f}-{max(loads):.1f}")
for i, (*_, kind) in enumerate(cases):
    print(f"  edit {i:2d} {kind:17s} new {best['new'][i]:7.1f} ms  main {best['main'][i]:7.1f} ms  ratio {ratio[i]:.3f}")
print(f"new/main geometric mean {np.exp(np.log(ratio).mean()):.3f} [{np.quantile(boot, 0.025):.3f}, "
      f"{np.quantile(boot, 0.975):.3f}] (paired bootstrap 95 %, 10k), wins {int((ratio < 1).sum())} / losses "
      f"{int((ratio > 1).sum())}; median new {np.median(best['new']):.1f} ms, main {np.median(best['main']):.1f} ms; "
      f"saved {np.mean(best['main'] - best['new']):.1f} ms per edit (mean)")
print("pictures (image, source, parts) of the two arms equal:", same)
