# ruff: noqa: E501, E701, E702
"""paired.py LABEL BASE_RUN:NEW_RUN [BASE_RUN:NEW_RUN ...]: Table 1 photo rows (results.json of sdn3d-bench runs),
entries pooled over the pairs of runs (one pair per tree): per weather and kind, 3D-SDN new minus base and 3D-SDN minus
the 2D paste for base and new, on PSNR and L1 of 'all' and PSNR of 'objects'; mean, 10k-draw paired bootstrap 95 %
interval (seed 0), wins/losses (L1: lower is better, so its differences are base minus new and 2D minus 3D)."""
import json
import sys

import numpy as np


def load(run):
    r = json.load(open(f"{run}/results.json"))
    out = {}
    for e in list(r["entries"].values())[0]:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m:
            out[e["index"]] = (e["edit_kind"], e["key"].split(" ")[0].split("/")[1], m["3d-sdn"], m["2d"])
    return out


def ci(d):
    d = np.asarray([x for x in d if np.isfinite(x)])
    if not len(d): return "n=0"
    bt = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n {len(d)})"


label, pairs = sys.argv[1], [p.split(":") for p in sys.argv[2:]]
rows = []
for b, n in pairs:
    a, c = load(b), load(n)
    rows += [(a[i], c[i]) for i in sorted(set(a) & set(c))]
print(f"== {label}: {len(rows)} entries from {len(pairs)} tree(s); new = {', '.join(p[1] for p in pairs)}; base = {', '.join(p[0] for p in pairs)}")
for metric, region, sign in (("psnr", "all", 1), ("l1", "all", -1), ("psnr", "objects", 1)):
    print(f"-- {metric} {region}" + (" (sign: positive = new / 3D-SDN better)" if sign < 0 else ""))
    for weather in ("ALL", "clone", "rain"):
        for kind in ["ALL"] + sorted({r[0][0] for r in rows}):
            sel = [r for r in rows if (kind == "ALL" or r[0][0] == kind) and (weather == "ALL" or r[0][1] == weather)
                   and region in r[0][2] and region in r[1][2]]
            if not sel or (region == "objects" and weather != "ALL"): continue
            nb = [sign * (r[1][2][region][metric] - r[0][2][region][metric]) for r in sel]
            db = [sign * (r[0][2][region][metric] - r[0][3][region][metric]) for r in sel]
            dn = [sign * (r[1][2][region][metric] - r[1][3][region][metric]) for r in sel]
            print(f"{weather:5s} {kind:16s} new-base {ci(nb)} | 3D-2D base {ci(db)} | new {ci(dn)}")
