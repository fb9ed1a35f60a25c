# ruff: noqa: INP001, E501
"""kinds.py MAIN LANE: per edit kind of a Table 1 predicted photo row (results.json in each directory): 3D-SDN minus
the 2D paste on PSNR all in each arm, and lane minus main on 3D-SDN's PSNR all paired by entry (mean, 95 % bootstrap
interval over entries, 4000 draws, seed 0; entries, not car groups: a small tree's check, not a claim)."""
import json
import sys

import numpy as np

(a,) = json.load(open(sys.argv[1] + "/results.json"))["entries"].values()
(b,) = json.load(open(sys.argv[2] + "/results.json"))["entries"].values()
rng = np.random.default_rng(0)


def psnr(r, method):
    return r["metrics"]["photo"][method]["all"]["psnr"]


for kind in sorted({r["edit_kind"] for r in a}):
    pa = {r["index"]: r for r in a if r["edit_kind"] == kind}
    pb = {r["index"]: r for r in b if r["edit_kind"] == kind}
    keys = sorted(set(pa) & set(pb))
    ga = np.array([psnr(pa[k], "3d-sdn") - psnr(pa[k], "2d") for k in keys])
    gb = np.array([psnr(pb[k], "3d-sdn") - psnr(pb[k], "2d") for k in keys])
    d = np.array([psnr(pb[k], "3d-sdn") - psnr(pa[k], "3d-sdn") for k in keys])
    boot = d[rng.integers(0, len(d), (4000, len(d)))].mean(1)
    print(f"{kind:17s} n {len(keys):3d}: 3D-2D main {ga.mean():+.2f}, lane {gb.mean():+.2f}; lane - main (3D-SDN) "
          f"{d.mean():+.2f} [{np.percentile(boot, 2.5):+.2f}, {np.percentile(boot, 97.5):+.2f}]")
