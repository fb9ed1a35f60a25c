"""blur_same.py: OpenCV's Gaussian blur of a float32 picture at sigma (s, 1), cut to some rows and the blur's reach
around them (road._blur_reach(1) = 5 >= OpenCV's 4), gives the whole picture's blur on those rows bit for bit
(40 random pictures, sizes, sigmas and row ranges); and its time on the whole box against a quarter of its rows."""

import time

import cv2
import numpy as np

rng = np.random.default_rng(0)
bad = 0
for _ in range(40):
    h, w = int(rng.integers(50, 400)), int(rng.integers(100, 1300))
    img = rng.random((h, w), dtype=np.float32) * (rng.random((h, w)) > 0.3).astype(np.float32)
    sigma = float(rng.uniform(1, 80))
    full = cv2.GaussianBlur(img, (0, 0), sigma, sigmaY=1.0)
    r0 = int(rng.integers(0, h - 1))
    r1 = int(rng.integers(r0 + 1, h + 1))
    a, b = max(r0 - 4, 0), min(r1 + 4, h)
    part = cv2.GaussianBlur(np.ascontiguousarray(img[a:b]), (0, 0), sigma, sigmaY=1.0)
    if not np.array_equal(full[r0:r1].view(np.uint32), part[r0 - a:r1 - a].view(np.uint32)):
        bad += 1
        print("different", h, w, sigma, r0, r1)
print("different cases:", bad, "OpenCV", cv2.__version__)
img = rng.random((375, 965), dtype=np.float32)
for rows in (375, 105):
    t0 = time.perf_counter()
    for _ in range(5):
        cv2.GaussianBlur(img[:rows].copy(), (0, 0), 74.0, sigmaY=1.0)
    print(rows, "rows:", round((time.perf_counter() - t0) / 5 * 1000, 1), "ms")
