# ruff: noqa: E402, E501, E701, E702
"""flipcap.py CAP.pt...: per variation, the fitted proposal vehicles (matched to the ground truth, IoU >= 0.3) whose
fitted yaw is over 90 degrees off the truth (ground-truth geometry, oracle), and the median yaw error."""
import math
import sys

import numpy as np
import torch


def err(a, b): return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))
for f in sys.argv[1:]:
    rows = torch.load(f, weights_only=False)
    for v in sorted({r["var"] for r in rows}):
        e = np.array([err(r["fit_ry"], r["true_ry"]) for r in rows if r["var"] == v])
        print(f"{f.split('/')[-1]:24s} {v:6s} n {len(e):3d} flips {(e > 90).sum():3d} ({100 * (e > 90).mean():4.1f} %) median yaw err {np.median(e):6.1f}")
