# ruff: noqa: E501, E701, E702
"""cmp.py BASE_PREFIX NEW_PREFIX SOURCE SEED...: Table 1 photo rows (PSNR all), per weather and kind: 3D-SDN new minus
base, and 3D-SDN minus 2D for base and new (entries pooled over the seeds; 10k paired bootstrap, seed 0; wins/losses).
Runs are /tmp/s12data/cutmask/runs/<PREFIX><SEED>_<SOURCE>/results.json."""
import json
import sys

import numpy as np

D = "/tmp/s12data/cutmask/runs/"
bp, np_, src = sys.argv[1:4]; seeds = sys.argv[4:]
METRIC = "psnr"


def load(prefix):
    out = {}
    for s in seeds:
        r = json.load(open(f"{D}{prefix}{s}_{src}/results.json"))
        for e in list(r["entries"].values())[0]:
            m = ((e.get("metrics") or {}).get("photo") or {})
            if "3d-sdn" in m and "2d" in m:
                weather = e["key"].split(" ")[0].split("/")[1]
                out[(s, e["index"])] = (e["edit_kind"], weather, m["3d-sdn"]["all"][METRIC], m["2d"]["all"][METRIC], m["3d-sdn"]["objects"][METRIC], m["2d"]["objects"][METRIC])
    return out


def ci(d):
    d = np.asarray([x for x in d if np.isfinite(x)])
    if not len(d): return "n=0"
    rng = np.random.default_rng(0)
    bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] {int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n={len(d)})"


a, b = load(bp), load(np_)
ks = sorted(set(a) & set(b))
print(f"== {src}, seeds {' '.join(seeds)}: {np_} vs {bp}; PSNR all (dB)")
for weather in ["ALL", "clone", "rain"]:
    for kind in ["ALL"] + sorted({a[k][0] for k in ks}):
        kk = [k for k in ks if (kind == "ALL" or a[k][0] == kind) and (weather == "ALL" or a[k][1] == weather)]
        if not kk: continue
        print(f"{weather:6s} {kind:17s} new-base {ci([b[k][2] - a[k][2] for k in kk])} | 3D-2D base {ci([a[k][2] - a[k][3] for k in kk])} | new {ci([b[k][2] - b[k][3] for k in kk])}")
print(f"{'objects (all)':24s} new-base {ci([b[k][4] - a[k][4] for k in ks])} | 3D-2D base {ci([a[k][4] - a[k][5] for k in ks])} | new {ci([b[k][4] - b[k][5] for k in ks])}")
