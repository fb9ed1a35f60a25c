# ruff: noqa: E402, E501, E701, E702
"""cf_cmp.py BASE_JSON NEW_JSON: the counterfactual bench's photo:auto PSNR, new - base, paired per pair: turns per
angle bin (the car's PSNR, as session 6's turns_cmp.py) and deletes (the vacated hole's PSNR); mean, 10k paired
bootstrap 95 % interval, new better / worse pairs."""
import json
import sys

import numpy as np


def load(p):
    out = {}
    for q in json.load(open(p))["pairs"]:
        m = q.get("metrics", {}).get("photo:auto")
        if not m: continue
        region = "car" if q["kind"] == "turn" else "hole"
        if region in m: out[(q["source"], q["key"])] = (q["bin"], m[region]["psnr"])
    return out


a, b = load(sys.argv[1]), load(sys.argv[2])
rng = np.random.default_rng(0)
keys = sorted(set(a) & set(b))
print("| bin | n | base PSNR | new PSNR | new - base [95 % CI] | new better / worse |")
print("|---|---|---|---|---|---|")
bins = sorted({a[k][0] for k in keys}, key=lambda s: (s == "delete", float(s.split()[1]) if " " in s else 0))
for bn in bins + ["all turns"]:
    ks = [k for k in keys if (a[k][0] == bn or (bn == "all turns" and a[k][0] != "delete"))]
    d = np.array([b[k][1] - a[k][1] for k in ks])
    boots = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    print(f"| {bn} | {len(ks)} | {np.mean([a[k][1] for k in ks]):.3f} | {np.mean([b[k][1] for k in ks]):.3f} | {d.mean():+.5f} [{np.percentile(boots, 2.5):+.5f}, {np.percentile(boots, 97.5):+.5f}] | {int((d > 1e-9).sum())} / {int((d < -1e-9).sum())} |")
