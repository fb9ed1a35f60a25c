"""3D-SDN's PSNR (all) of two sdn3d-bench results over the same entries, new - old per kind of edit: mean, 95 %
bootstrap interval, better / worse entries, per source scene.

    python paired_by_kind.py OLD/results.json NEW/results.json
"""

import json
import sys

import numpy as np

old, new = (json.load(open(path)) for path in sys.argv[1:3])
rng = np.random.default_rng(0)
for src in old["entries"]:
    a = {e["key"] + str(e["index"]): e for e in old["entries"][src]}
    rows: dict[str, list[float]] = {}
    for e in new["entries"][src]:
        before = a.get(e["key"] + str(e["index"]))
        mb, ma = (e.get("metrics") or {}).get("photo"), ((before or {}).get("metrics") or {}).get("photo")
        if not ma or not mb or "3d-sdn" not in ma or "3d-sdn" not in mb:
            continue
        d = mb["3d-sdn"]["all"]["psnr"] - ma["3d-sdn"]["all"]["psnr"]
        rows.setdefault(e.get("edit_kind", "?"), []).append(d)
    for kind, values in sorted(rows.items()):
        d = np.array(values)
        boot = [rng.choice(d, len(d)).mean() for _ in range(4000)]
        low, high = np.percentile(boot, [2.5, 97.5])
        print(f"{src:9s} {kind:17s} n={len(d):3d} new-old {d.mean():+.2f} [{low:+.2f}, {high:+.2f}] "
              f"better/worse {int((d > 1e-6).sum())}/{int((d < -1e-6).sum())}")
