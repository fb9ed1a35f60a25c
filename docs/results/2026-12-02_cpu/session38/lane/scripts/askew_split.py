# ruff: noqa: INP001, E501
"""askew_split.py JSON... : per row, objects split by how far their true yaw lies from the road's axis (camera yaw 0:
the axis is ry = +-90 degrees), aligned (<= 10 degrees) against askew (> 10): matched median / p90 yaw error, over 20,
flips (unmatched counted)."""
import json
import math
import sys

import numpy as np

for p in sys.argv[1:]:
    d = json.load(open(p))
    for row, objs in d["objects"].items():
        for name, sel in (("aligned", lambda o: o["off"] <= 10), ("askew", lambda o: o["off"] > 10)):
            for o in objs:
                o["off"] = abs(math.degrees(math.atan2(math.sin(2 * (o["true_ry"] - math.pi / 2)), math.cos(2 * (o["true_ry"] - math.pi / 2))) / 2))
            s = [o for o in objs if sel(o)]
            m = [o for o in s if o.get("matched", True)]
            if not m:
                continue
            y = np.array([o["yaw_deg"] for o in m])
            print(f"{p.split('/')[-1]:16s} {row[:34]:34s} {name:8s} n {len(s):3d} matched {len(m):3d}: median {np.median(y):6.2f} p90 {np.percentile(y, 90):6.1f} over20 {np.mean(y > 20):.3f} flips {sum(o['yaw_deg'] > 90 for o in s)}")
