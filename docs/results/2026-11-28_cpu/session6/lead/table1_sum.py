# ruff: noqa: E501
"""3D-SDN minus 2D (PSNR, L1; all, objects) per source for a photo-mode sdn3d-bench results.json, and per kind PSNR
all; 95 % paired bootstrap (10,000 draws, seed 0), wins/losses.   python table1_sum.py RESULTS.json [LABEL]"""
import json
import sys

import numpy as np


def ci(d):
    d = np.asarray([x for x in d if np.isfinite(x)])
    rng = np.random.default_rng(0)
    boot = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return d.mean(), lo, hi, int((d > 1e-9).sum()), int((d < -1e-9).sum()), len(d)


res = json.load(open(sys.argv[1]))
label = sys.argv[2] if len(sys.argv) > 2 else sys.argv[1]
for src, entries in res["entries"].items():
    ms = [((e.get("metrics") or {}).get("photo") or {}, e.get("edit_kind")) for e in entries]
    ms = [(m, k) for m, k in ms if "3d-sdn" in m and "2d" in m]
    cells = []
    for metric, fmt in (("psnr", "{:+.2f} [{:+.2f}, {:+.2f}] {}/{}"), ("l1", "{:+.4f} [{:+.4f}, {:+.4f}] {}/{}")):
        for region in ("all", "objects"):
            d = [m["3d-sdn"][region][metric] - m["2d"][region][metric] for m, _ in ms if region in m["3d-sdn"]]
            mean, lo, hi, w, l_, n = ci(d)
            if metric == "l1":
                w, l_ = l_, w  # lower L1 is better
            cells.append(fmt.format(mean, lo, hi, w, l_) + f" (n={n})")
    print(f"| {label} | {src} | " + " | ".join(cells) + " |")
    kinds = sorted({k for _, k in ms})
    print("   by kind, PSNR all: " + "; ".join(
        "{}: {:+.2f} [{:+.2f}, {:+.2f}] {}/{} (n={})".format(k, *ci([m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"] for m, kk in ms if kk == k])) for k in kinds))
