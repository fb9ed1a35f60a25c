# ruff: noqa: E501
"""group_cost.py: group_vehicles on tuning tree 35's 32 raw 312x96 frames (comp's captures, demo weights), one frame at a
time, with part_separation 4.0 (main now) and None (the session start's grouping); 5 rounds, taking turns; per-frame
median ms of each and the ratio."""
import statistics
import time

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

torch.set_num_threads(1)
raw = torch.load("/tmp/s20data/comp/raw35_312.pt", weights_only=False)
g = dict(GROUPING_DEFAULTS)
times = {4.0: [], None: []}
for _ in range(5):
    for fr in raw["frames"].values():
        prob = fr["logits"][None].softmax(1)
        label = prob.argmax(1)
        for part in (4.0, None):
            t = time.perf_counter()
            group_vehicles(label, prob, fr["center"][None], fr["offset"][None], raw["things"], thing_odds=g["thing_odds"],
                           threshold=g["center_threshold"], nms_kernel=g["nms_kernel"], top_k=g["top_k"],
                           min_area=g["min_area"], split_separation=g["split_separation"], part_separation=part)
            times[part].append((time.perf_counter() - t) * 1e3)
a, b = statistics.median(times[4.0]), statistics.median(times[None])
print(f"{len(times[None])} calls each: median ms part_separation=4.0 {a:.2f}, None {b:.2f}; max {max(times[4.0]):.1f} / "
      f"{max(times[None]):.1f}")
