# ruff: noqa: E402, E501, E701, E702
"""v13pair.py BASE.json NEW.json: per row of the val13 pose table, objects whose flip (yaw error over 90 degrees)
changed (fixed/broken) and the paired change of the yaw error (10k bootstrap over objects, seed 0)."""
import json
import sys

import numpy as np

a, b = (json.load(open(f))["objects"] for f in sys.argv[1:3])
for row in a:
    x, y = a[row], b[row]
    ya = np.array([o["yaw_deg"] for o in x]); yb = np.array([o["yaw_deg"] for o in y])
    d = yb - ya; rng = np.random.default_rng(0); bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    fixed = int(((ya > 90) & (yb <= 90)).sum()); broken = int(((ya <= 90) & (yb > 90)).sum())
    print(f"{row:42s} n {len(d)} flips {int((ya > 90).sum())} -> {int((yb > 90).sum())} (fixed {fixed} / broken {broken}); mean yaw error change {d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] deg, better/worse {int((d < -1e-6).sum())}/{int((d > 1e-6).sum())}")
