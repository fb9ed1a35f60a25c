# ruff: noqa: INP001, E501, E702
"""paired.py MAIN.json SHARP.json: per row, the two arms' pose figures and the paired difference (sharp - main) of the share of cars over 20 degrees and of the median yaw error, 95 % bootstrap over cars (10,000 resamples, seed 0)."""
import json
import sys

import numpy as np

a, b = (json.load(open(p)) for p in sys.argv[1:3])
rng = np.random.default_rng(0)
for row in a["objects"]:
    ka = {(o["frame"], o["id"]): o for o in a["objects"][row]}
    kb = {(o["frame"], o["id"]): o for o in b["objects"][row]}
    keys = sorted(set(ka) & set(kb))
    ya = np.array([ka[k]["yaw_deg"] for k in keys]); yb = np.array([kb[k]["yaw_deg"] for k in keys])
    da = np.array([ka[k]["dist"] for k in keys]); db = np.array([kb[k]["dist"] for k in keys])
    idx = rng.integers(0, len(keys), (10000, len(keys)))
    over = (yb[idx] > 20).mean(1) - (ya[idx] > 20).mean(1)
    med = np.median(yb[idx], 1) - np.median(ya[idx], 1)
    print(f"{row} (n={len(keys)}):")
    for name, y, d in (("main", ya, da), ("sharp", yb, db)):
        print(f"   {name:5s}: median {np.median(y):5.1f}  p90 {np.percentile(y, 90):5.1f}  over 20 {np.mean(y > 20):.3f}  flips {np.mean(y > 90):.3f}  distance median x1e-2 {np.median(d) * 100:5.1f}")
    print(f"   sharp - main: over 20 {np.mean(yb > 20) - np.mean(ya > 20):+.3f} [{np.percentile(over, 2.5):+.3f}, {np.percentile(over, 97.5):+.3f}];"
          f" median {np.median(yb) - np.median(ya):+.1f} [{np.percentile(med, 2.5):+.1f}, {np.percentile(med, 97.5):+.1f}];"
          f" better / worse by over 5 degrees {int(np.sum(yb < ya - 5))} / {int(np.sum(yb > ya + 5))}; identical {int(np.sum(ya == yb))}")
