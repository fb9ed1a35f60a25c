# ruff: noqa: INP001, E501
"""kinds.py RUN: per kind of edit, 3D-SDN minus the 2D paste on PSNR and L1 (all), paired by entry, 95 % bootstrap
over car groups (as arms.py), and the win count."""
import json
import sys

import numpy as np
from groups import group_key, group_mean

(entries,) = json.load(open(sys.argv[1] + "/results.json"))["entries"].values()
rng = np.random.default_rng(0)
for metric in ("psnr", "l1"):
    print(f"{sys.argv[1]}: 3D-SDN minus 2D, {metric} (all)")
    for kind in sorted({r["edit_kind"] for r in entries}) + ["all kinds"]:
        rows = [r for r in entries if kind == "all kinds" or r["edit_kind"] == kind]
        groups = {}
        for r in rows:
            m = r["metrics"]["photo"]
            groups.setdefault(group_key(r), []).append(m["3d-sdn"]["all"][metric] - m["2d"]["all"][metric])
        mean, low, high = group_mean(groups, rng)
        d = [v for g in groups.values() for v in g]
        better = sum((x > 0) if metric == "psnr" else (x < 0) for x in d)
        fmt = "+.2f" if metric == "psnr" else "+.4f"
        print(f"  {kind:17s} {len(rows):3d} entries, {len(groups):2d} groups: {mean:{fmt}} "
              f"[{low:{fmt}}, {high:{fmt}}], 3D-SDN better {better} / {len(d)}")
