"""Paired difference of 3D-SDN's PSNR between two sdn3d-bench results over the same entries (new - old): mean, 95 %
bootstrap interval, better / worse / tied entries, per source scene and region.

    python paired_runs.py OLD/results.json NEW/results.json
"""

import json
import sys

import numpy as np

old, new = (json.load(open(path)) for path in sys.argv[1:3])
rng = np.random.default_rng(0)


def photo(entry: dict) -> dict | None:
    metrics = (entry.get("metrics") or {}).get("photo")
    return metrics if metrics and "3d-sdn" in metrics else None


for src in old["entries"]:
    a = {e["key"] + str(e["index"]): e for e in old["entries"][src]}
    b = {e["key"] + str(e["index"]): e for e in new["entries"][src]}
    for region in ("all", "objects"):
        d = []
        for key, entry in a.items():
            ma, mb = photo(entry), photo(b.get(key, {}))
            if ma and mb and region in ma["3d-sdn"] and region in mb["3d-sdn"]:
                d.append(mb["3d-sdn"][region]["psnr"] - ma["3d-sdn"][region]["psnr"])
        d = np.array(d)
        d = d[np.isfinite(d)]
        if not len(d):
            continue
        boot = [rng.choice(d, len(d)).mean() for _ in range(4000)]
        low, high = np.percentile(boot, [2.5, 97.5])
        counts = f"{int((d > 1e-6).sum())}/{int((d < -1e-6).sum())}/{int((abs(d) <= 1e-6).sum())}"
        print(f"{src:9s} PSNR({region}) new-old {d.mean():+.2f} [{low:+.2f}, {high:+.2f}] better/worse/tie {counts} "
              f"n={len(d)}")
