# ruff: noqa: E501, E702
"""micro.py: ray_fill (road.py) at 1242x375 with vanishing near and telea, alternated, 5 calls each: a car-sized hole with the
vanishing point far left (the real frame's), a thin occluder's hole in front of a kept car, and the car hole with the point
above its middle (noise on random texture; the timings of the fill alone, threads 1)."""
import time

import torch

from sdn3d.editing.photo.road import ray_fill

torch.manual_seed(0)
H, W = 375, 1242
img = torch.rand(3, H, W) * 0.2 + 0.4
hole = torch.zeros(H, W, dtype=torch.bool); hole[200:330, 700:920] = True   # a car's hole, vp far left
ko = torch.zeros(H, W, dtype=torch.bool); ko[190:300, 460:680] = True
pole = torch.zeros(H, W, dtype=torch.bool); pole[150:330, 800:812] = True   # a thin occluder in front of a kept car
ko2 = torch.zeros(H, W, dtype=torch.bool); ko2[220:320, 740:900] = True; ko2 &= ~pole
for name, h, k, vp in (("car hole", hole, ko, (218.6, 187.0)), ("pole", pole, ko2, (218.6, 187.0)), ("car hole vp centre", hole, ko, (620.0, 187.0))):
    for mode in ("near", "telea", "near", "telea"):
        t = time.perf_counter()
        for _ in range(5):
            ray_fill(img, h, vp, k, 0.0, 0.25, 12, match_grain=True, marks=0.2, vanishing=mode)
        print(name, mode, f"{(time.perf_counter() - t) / 5 * 1000:.1f} ms")
