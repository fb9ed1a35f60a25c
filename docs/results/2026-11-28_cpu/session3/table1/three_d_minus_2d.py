"""3D-SDN minus the 2D paste per entry of one sdn3d-bench result (photo mode): mean, 95 % bootstrap interval and how
many entries 3D-SDN wins, per source scene, region (all, objects) and metric (PSNR, L1).

    python three_d_minus_2d.py RESULTS.json
"""

import json
import sys

import numpy as np

result = json.load(open(sys.argv[1]))
rng = np.random.default_rng(0)
for src, entries in result["entries"].items():
    for region in ("all", "objects"):
        for metric in ("psnr", "l1"):
            d = []
            for e in entries:
                m = (e.get("metrics") or {}).get("photo") or {}
                if region in m.get("3d-sdn", {}) and region in m.get("2d", {}):
                    d.append(m["3d-sdn"][region][metric] - m["2d"][region][metric])
            d = np.array(d)
            d = d[np.isfinite(d)]
            boot = [rng.choice(d, len(d)).mean() for _ in range(4000)]
            low, high = np.percentile(boot, [2.5, 97.5])
            better = (d > 0) if metric == "psnr" else (d < 0)
            print(f"{src:9s} {metric}({region}) 3D-2D {d.mean():+.4f} [{low:+.4f}, {high:+.4f}] "
                  f"3D better {int(better.sum())}/{len(d)}")
