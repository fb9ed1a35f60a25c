# ruff: noqa: E402, E501, E701, E702
"""cmp.py BASE_PREFIX NEW_PREFIX SOURCE SEED...: Table 1 photo rows, per kind: 3D-SDN's PSNR all new minus base, and
3D-SDN minus 2D for base and new (entries pooled over the seeds' trees; 10k paired bootstrap, seed 0; wins/losses).
Runs are runs/<PREFIX><SEED>_<SOURCE>/results.json."""
import json
import sys

import numpy as np

D = "/tmp/s11data/lead/runs/"
bp, np_, src = sys.argv[1:4]; seeds = sys.argv[4:]


def load(prefix):
    out = {}
    for s in seeds:
        r = json.load(open(f"{D}{prefix}{s}_{src}/results.json"))
        for e in list(r["entries"].values())[0]:
            m = ((e.get("metrics") or {}).get("photo") or {})
            if "3d-sdn" in m and "2d" in m:
                out[(s, e["index"])] = (e["edit_kind"], m["3d-sdn"]["all"]["psnr"], m["2d"]["all"]["psnr"], m["3d-sdn"]["objects"]["psnr"], m["2d"]["objects"]["psnr"])
    return out


def ci(d):
    d = np.asarray([x for x in d if np.isfinite(x)]); rng = np.random.default_rng(0)
    bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] {int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n={len(d)})"


a, b = load(bp), load(np_)
ks = sorted(set(a) & set(b))
print(f"== {src}, seeds {' '.join(seeds)}: {np_} vs {bp}")
for kind in ["ALL"] + sorted({a[k][0] for k in ks}):
    kk = [k for k in ks if kind == "ALL" or a[k][0] == kind]
    print(f"{kind:17s} new-base {ci([b[k][1] - a[k][1] for k in kk])} | 3D-2D base {ci([a[k][1] - a[k][2] for k in kk])} | new {ci([b[k][1] - b[k][2] for k in kk])}")
kk = ks
print(f"{'objects (all)':17s} new-base {ci([b[k][3] - a[k][3] for k in kk])} | 3D-2D base {ci([a[k][3] - a[k][4] for k in kk])} | new {ci([b[k][3] - b[k][4] for k in kk])}")
