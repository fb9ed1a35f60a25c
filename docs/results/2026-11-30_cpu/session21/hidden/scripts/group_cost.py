# ruff: noqa: E501
"""group_cost.py (session 20 lead's, adapted): group_vehicles on tuning tree 35's 32 raw 312x96 frames (raw.py's file,
session 21's demo weights), one frame at a time, with stray_distance at the branch's default and None (main's grouping),
the other settings GROUPING_DEFAULTS; 5 rounds, taking turns; per-frame median ms of each. Run from the worktree root:
PYTHONPATH=src OMP_NUM_THREADS=1 python group_cost.py"""
import statistics
import time

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

torch.set_num_threads(1)
raw = torch.load("/tmp/s21data/hidden/raw35_312.pt", weights_only=False)
g = dict(GROUPING_DEFAULTS)
STRAY = GROUPING_DEFAULTS["stray_distance"]
times = {STRAY: [], None: []}
for _ in range(5):
    for fr in raw["frames"].values():
        prob = fr["logits"][None].softmax(1)
        label = prob.argmax(1)
        for part in (STRAY, None):
            t = time.perf_counter()
            group_vehicles(label, prob, fr["center"][None], fr["offset"][None], raw["things"], thing_odds=g["thing_odds"],
                           threshold=g["center_threshold"], nms_kernel=g["nms_kernel"], top_k=g["top_k"],
                           min_area=g["min_area"], split_separation=g["split_separation"], part_separation=g["part_separation"], stray_distance=part, stray_reach=g["stray_reach"])
            times[part].append((time.perf_counter() - t) * 1e3)
a, b = statistics.median(times[STRAY]), statistics.median(times[None])
print(f"{len(times[None])} calls each: median ms stray_distance={STRAY} {a:.2f}, None {b:.2f}; max {max(times[STRAY]):.1f} / "
      f"{max(times[None]):.1f}")
