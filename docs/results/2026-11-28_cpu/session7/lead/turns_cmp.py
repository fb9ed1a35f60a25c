# ruff: noqa: E402, E501, E701, E702
"""turns_cmp.py BASE_JSON NEW_JSON: paired per-bin car PSNR / L1 / flat of photo:auto (new - base), 10k bootstrap."""
import json
import sys

import numpy as np


def load(p):
    d = json.load(open(p)); out = {}
    for q in d["pairs"]:
        if q["kind"] != "turn" or "photo:auto" not in q.get("metrics", {}): continue
        out[(q["source"], q["key"])] = (q["bin"], q["metrics"]["photo:auto"]["car"], q["metrics"].get("2d", {}).get("car"))
    return out
a, b = load(sys.argv[1]), load(sys.argv[2])
rng = np.random.default_rng(0)
keys = sorted(set(a) & set(b))
for src in sorted({k[0] for k in keys}):
    for bn in sorted({a[k][0] for k in keys}, key=lambda s: float(s.split()[1])):
        ks = [k for k in keys if k[0] == src and a[k][0] == bn]
        d = np.array([b[k][1]["psnr"] - a[k][1]["psnr"] for k in ks])
        boots = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
        fa = np.mean([a[k][1]["flat"] for k in ks]) * 100; fb = np.mean([b[k][1]["flat"] for k in ks]) * 100
        pa = np.mean([a[k][1]["psnr"] for k in ks]); pb = np.mean([b[k][1]["psnr"] for k in ks])
        d2 = [b[k][1]["psnr"] - b[k][2]["psnr"] for k in ks if b[k][2]]
        print(f"{src} {bn}: n={len(ks)} PSNR {pa:.2f} -> {pb:.2f}, diff {d.mean():+.3f} [{np.percentile(boots,2.5):+.3f}, {np.percentile(boots,97.5):+.3f}] {int((d>1e-6).sum())}/{int((d<-1e-6).sum())}; flat {fa:.1f} -> {fb:.1f} %; new-2D {np.mean(d2):+.2f}" )
