# ruff: noqa: E501, E701, E702
"""gate_sim.py BASE S13 SOURCE T...: simulated photo.paste_max_stretch=T from runs at 100 (BASE) and 1.3 (S13): an
entry takes S13's PSNR where its largest recorded paste_stretch exceeds T, else BASE's (exact where every pasted
object of the entry is over T or under 1.3); new minus base, 10k paired bootstrap"""
import json
import sys

import numpy as np

D = "/tmp/s11data/lead/runs/"
base, s13, src = sys.argv[1:4]


def load(name):
    r = json.load(open(f"{D}{name}_{src}/results.json"))
    return {e["index"]: (e["edit_kind"], e["metrics"]["photo"]["3d-sdn"]["all"]["psnr"]) for e in list(r["entries"].values())[0] if "3d-sdn" in ((e.get("metrics") or {}).get("photo") or {})}


a, b = load(base), load(s13)
picks = json.load(open(f"{D}{base}_{src}.picks.json"))
stretch = {}
for k, v in picks.items():
    s = [o["paste_stretch"] for rec in (v.get("objects") or []) for o in rec.values() if "paste_stretch" in o]
    stretch[int(k)] = max(s) if s else 0.0
for t in map(float, sys.argv[4:]):
    d = np.array([(b[k][1] if stretch.get(k, 0) > t else a[k][1]) - a[k][1] for k in sorted(set(a) & set(b))])
    bt = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    print(f"T={t}: {d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n={len(d)}; entries over T: {sum(stretch.get(k, 0) > t for k in a)})")
