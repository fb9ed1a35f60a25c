"""Photo-mode sdn3d-bench results: 3D-SDN minus 2D per kind and overall, and (with a second file) 3D-SDN new minus
old, PSNR of all / objects; mean, 95 % bootstrap interval, wins.   python compare.py NEW.json [OLD.json]"""
import json
import sys

import numpy as np

rng = np.random.default_rng(0)


def load(path):
    out = {}
    for src, entries in json.load(open(path))["entries"].items():
        for e in entries:
            m = (e.get("metrics") or {}).get("photo") or {}
            out[(src, e["key"] + str(e["index"]))] = (e.get("edit_kind", "?"), m)
    return out


def line(label, d):
    d = np.array([x for x in d if np.isfinite(x)])
    if not len(d):
        return
    boot = [rng.choice(d, len(d)).mean() for _ in range(2000)]
    lo, hi = np.percentile(boot, [2.5, 97.5])
    print(f"  {label:34s} n={len(d):3d} {d.mean():+.2f} [{lo:+.2f}, {hi:+.2f}] wins {int((d > 1e-6).sum())}/"
          f"{int((d < -1e-6).sum())}")


new = load(sys.argv[1])
old = load(sys.argv[2]) if len(sys.argv) > 2 else None
for src in sorted({k[0] for k in new}):
    keys = [k for k in new if k[0] == src]
    kinds = sorted({new[k][0] for k in keys})
    for region in ("all", "objects"):
        print(f"{src} PSNR({region})")
        for kind in kinds + ["ALL"]:
            ks = [k for k in keys if kind == "ALL" or new[k][0] == kind]
            d = [new[k][1]["3d-sdn"][region]["psnr"] - new[k][1]["2d"][region]["psnr"] for k in ks
                 if "3d-sdn" in new[k][1] and "2d" in new[k][1]]
            line(f"{kind} 3D-2D", d)
            if old:
                d = [new[k][1]["3d-sdn"][region]["psnr"] - old[k][1]["3d-sdn"][region]["psnr"] for k in ks
                     if k in old and "3d-sdn" in new[k][1] and "3d-sdn" in old[k][1]]
                line(f"{kind} new-old", d)
