# ruff: noqa: E402, E501, E701, E702
"""t1_pair.py BASE FINAL: 3D-SDN's own PSNR all (and objects), final - base, overall and per kind (and variation), 10k paired bootstrap."""
import json
import sys

import numpy as np


def load(p):
    r = json.load(open(p)); out = {}
    for src, es in r["entries"].items():
        for i, e in enumerate(es):
            m = ((e.get("metrics") or {}).get("photo") or {}).get("3d-sdn")
            if m: out[(src, e.get("id", i))] = (e.get("edit_kind"), m["all"]["psnr"], m.get("objects", {}).get("psnr"), e["key"].split()[0].split("/")[1])
    return out
a, b = load(sys.argv[1]), load(sys.argv[2])
rng = np.random.default_rng(0)
def ci(d):
    d = np.asarray(d); bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] {int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n={len(d)})"
ks = sorted(set(a) & set(b), key=str)
print("all:", ci([b[k][1] - a[k][1] for k in ks]))
ko = [k for k in ks if a[k][2] is not None and b[k][2] is not None and np.isfinite(a[k][2]) and np.isfinite(b[k][2])]
print("objects:", ci([b[k][2] - a[k][2] for k in ko]))
for kind in sorted({a[k][0] for k in ks}):
    print(f"  {kind}:", ci([b[k][1] - a[k][1] for k in ks if a[k][0] == kind]))
    for var in sorted({a[k][3] for k in ks}):
        d = [b[k][1] - a[k][1] for k in ks if a[k][0] == kind and a[k][3] == var]
        if d: print(f"    {var}:", ci(d))
