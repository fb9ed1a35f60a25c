# ruff: noqa: E401, E402, E501, E701, E702, B023, F401, F841, I001
"""A probe of one cost this helper looked at and did not cut (README section 4); run from the worktree with
PYTHONPATH=src, threads 1."""
import time, torch, numpy as np
from sdn3d.editing.photo import road
torch.set_num_threads(1)
import cv2; cv2.setNumThreads(1)
g = torch.Generator().manual_seed(0)
img = torch.rand(3, 375, 1242, generator=g)
hole = torch.zeros(375, 1242, dtype=torch.bool); hole[200:280, 500:700] = True
valid = ~hole
def t(f, n=7):
    best = 1e9
    for _ in range(n):
        t0 = time.process_time(); f(); best = min(best, time.process_time() - t0)
    return 1000 * best
print("normalised_blur s1", t(lambda: road._normalised_blur(img, valid, 1.0)))
print("normalised_blur grain", t(lambda: road._normalised_blur(img, valid, road.GRAIN_SIGMA)))
print("coarse", t(lambda: road._coarse_blur(img, valid, road.MARK_SIGMA)))
print("detail chain", t(lambda: (img - road._normalised_blur(img, valid, road.GRAIN_SIGMA)) * valid))
full = road._normalised_blur(img, valid, 1.0)
for y0, y1, x0, x1 in [(100, 375, 300, 900), (37, 301, 13, 1001)]:
    crop = road._normalised_blur(img[:, y0:y1, x0:x1], valid[y0:y1, x0:x1], 1.0)
    m = 8
    print("crop equal interior", torch.equal(crop[:, m:-m, m:-m], full[:, y0 + m:y1 - m, x0 + m:x1 - m]),
          (crop[:, m:-m, m:-m] - full[:, y0 + m:y1 - m, x0 + m:x1 - m]).abs().max().item())
