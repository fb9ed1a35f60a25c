# ruff: noqa: INP001, E501
"""overall.py A B: 3D-SDN's own PSNR (all, objects) of a Table 1 photo row, B minus A over every entry both scored, paired by entry: mean and 95 % bootstrap interval (entries; 4000 draws, seed 0), and each arm's mean."""
import json
import sys

import numpy as np

(a,) = json.load(open(sys.argv[1] + "/results.json"))["entries"].values()
(b,) = json.load(open(sys.argv[2] + "/results.json"))["entries"].values()
rng = np.random.default_rng(0)
pa, pb = {r["index"]: r for r in a}, {r["index"]: r for r in b}
for region in ("all", "objects"):
    keys = [k for k in sorted(set(pa) & set(pb))
            if pa[k]["metrics"]["photo"]["3d-sdn"].get(region) and pb[k]["metrics"]["photo"]["3d-sdn"].get(region)
            and pa[k]["metrics"]["photo"]["3d-sdn"][region].get("psnr") is not None and pb[k]["metrics"]["photo"]["3d-sdn"][region].get("psnr") is not None]
    va = np.array([pa[k]["metrics"]["photo"]["3d-sdn"][region]["psnr"] for k in keys])
    vb = np.array([pb[k]["metrics"]["photo"]["3d-sdn"][region]["psnr"] for k in keys])
    ok = np.isfinite(va) & np.isfinite(vb)
    va, vb = va[ok], vb[ok]
    d = vb - va
    boot = d[rng.integers(0, len(d), (4000, len(d)))].mean(1)
    print(f"PSNR {region:8s} n {len(d):3d}: A {va.mean():.2f}  B {vb.mean():.2f}  B - A {d.mean():+.2f} [{np.percentile(boot, 2.5):+.2f}, {np.percentile(boot, 97.5):+.2f}]  better/worse {int((d > 0).sum())}/{int((d < 0).sum())}")
