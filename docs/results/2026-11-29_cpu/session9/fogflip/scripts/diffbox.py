# ruff: noqa: E402, E501, E701, E702
"""diffbox.py BASE.png NEW.png: the box (working pixels) where the 3D-SDN panels of two example sheets differ."""
import sys

import numpy as np
from PIL import Image

PW = 312
a, b = (np.asarray(Image.open(p).convert("RGB")).astype(int) for p in sys.argv[1:3])
W, H = a.shape[1], a.shape[0]; gap = (W - 5 * PW) // 4; top = H - 96
pa, pb = a[top:, 2 * (PW + gap):2 * (PW + gap) + PW], b[top:, 2 * (PW + gap):2 * (PW + gap) + PW]
d = np.abs(pa - pb).sum(2) > 10
ys, xs = np.nonzero(d)
print(f"{max(xs.min() - 8, 0)},{max(ys.min() - 8, 0)},{min(xs.max() + 9, PW)},{min(ys.max() + 9, 96)}" if len(xs) else "none")
