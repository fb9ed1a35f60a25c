# ruff: noqa: E402, E501, E701, E702, B007, F401, F841, B905
"""Simulate photo.paste_max_iou from a pasted run (with its objects log) and a no-paste run on the same entries.
python gate_sim.py PASTE_DIR PASTE_LOG NOPASTE_DIR [region]"""
import json
import sys

import numpy as np

rng = np.random.default_rng(0)


def entries(d):
    out = []
    for src, es in json.load(open(d + "/results.json"))["entries"].items():
        for e in es:
            m = (e.get("metrics") or {}).get("photo") or {}
            if "3d-sdn" in m:
                out.append((src, e["key"] + str(e["index"]), e.get("edit_kind"), m))
    return out


region = sys.argv[4] if len(sys.argv) > 4 else "all"
pa, no = entries(sys.argv[1]), entries(sys.argv[3])
logs = [json.loads(x) for x in open(sys.argv[2])]
assert len(logs) == len(pa), (len(logs), len(pa))
nod = {k: m for _, k, _, m in no}
rows = []
for (src, k, kind, m), lg in zip(pa, logs):
    ious = [o["outline_iou"] for o in lg["objects"].values() if "outline_iou" in o]
    pasted = any("mask" in o for o in lg["objects"].values())
    if k not in nod:
        continue
    p, n, two = m["3d-sdn"][region]["psnr"], nod[k]["3d-sdn"][region]["psnr"], m["2d"][region]["psnr"]
    rows.append((kind, min(ious) if ious else None, pasted, p, n, two))
cand = [r for r in rows if r[1] is not None]
print(f"{len(rows)} entries, {len(cand)} with a paste candidate; paste - nopaste on those by IoU:")
for lo, hi in ((0, .6), (.6, .7), (.7, .75), (.75, .8), (.8, .85), (.85, .9), (.9, 1.01)):
    d = np.array([r[3] - r[4] for r in cand if lo <= r[1] < hi])
    if len(d):
        print(f"  iou [{lo:.2f},{hi:.2f}) n={len(d):3d} mean {d.mean():+.2f} wins {int((d > 1e-6).sum())}/{int((d < -1e-6).sum())}")
for t in (0.0, 0.6, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 1.0):
    g = np.array([r[3] if (r[1] is not None and r[1] <= t) else r[4] for r in rows])
    d2 = g - np.array([r[5] for r in rows])
    dp = g - np.array([r[3] for r in rows])
    boot = [rng.choice(d2, len(d2)).mean() for _ in range(1000)]
    print(f"  t={t:.2f}: gated - 2D {d2.mean():+.3f} [{np.percentile(boot, 2.5):+.2f}, {np.percentile(boot, 97.5):+.2f}]"
          f"  gated - always {dp.mean():+.3f}")
