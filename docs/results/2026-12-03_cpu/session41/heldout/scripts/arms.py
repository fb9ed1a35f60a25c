# ruff: noqa: INP001, E501
"""arms.py A B [METHOD]: B minus A on METHOD's PSNR (all) (default 3d-sdn; 2d: the 2D paste) per kind and overall,
paired by entry, 95 % bootstrap over car groups (entries that edit the same cars resampled together, as
sdn3d-bench's "Who won"; 4000 draws, seed 0; groups.py). Session 40's arms.py with the method as an argument."""
import json
import sys

import numpy as np
from groups import group_key, group_mean


def load(folder):
    (entries,) = json.load(open(folder + "/results.json"))["entries"].values()
    return {r["index"]: r for r in entries}


a, b = load(sys.argv[1]), load(sys.argv[2])
method = sys.argv[3] if len(sys.argv) > 3 else "3d-sdn"
rng = np.random.default_rng(0)


def psnr(r):
    return r["metrics"]["photo"][method]["all"]["psnr"]


print(f"{sys.argv[2]} minus {sys.argv[1]}, {method}, PSNR (all):")
for kind in sorted({r["edit_kind"] for r in a.values()}) + ["all kinds"]:
    keys = [k for k in a if k in b and (kind == "all kinds" or a[k]["edit_kind"] == kind)]
    groups = {}
    for k in keys:
        groups.setdefault(group_key(a[k]), []).append(psnr(b[k]) - psnr(a[k]))
    mean, low, high = group_mean(groups, rng)
    print(f"  {kind:17s} {len(keys):3d} entries, {len(groups):2d} groups: {mean:+.2f} [{low:+.2f}, {high:+.2f}]")
