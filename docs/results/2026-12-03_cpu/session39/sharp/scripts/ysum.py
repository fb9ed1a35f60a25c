# ruff: noqa: INP001, E501, E401, E701, E702, B007, F401, I001
"""ysum.py JSON...: per file and row: matched n, median / p90 yaw error, over 20 degrees, flips, distance median, sil IoU median; askew split when true yaw is off the axis."""
import gzip, json, sys, math
import numpy as np
for path in sys.argv[1:]:
    d = json.load(gzip.open(path) if path.endswith('gz') else open(path))
    for row, objs in d['objects'].items():
        for name, sel in (("all", lambda o: True), ("aligned", lambda o: off(o) <= 10), ("askew", lambda o: off(o) > 10)):
            def off(o):
                a = (math.degrees(o['true_ry']) - 90) % 180
                return min(a, 180 - a)
            s = [o for o in objs if sel(o)]
            if not s:
                continue
            y = np.array([o['yaw_deg'] for o in s]); dist = np.array([o['dist'] for o in s])
            sil = np.array([o['sil_iou'] or 0 for o in s])
            print(f"{path.split('/')[-1]:32s} {row[:34]:34s} {name:8s} n={len(s):3d} median {np.median(y):5.1f} p90 {np.percentile(y,90):5.1f} >20 {np.mean(y>20):.3f} flips {np.mean(y>90):.3f} dist {np.median(dist)*100:5.1f} sil {np.median(sil):.3f}")
