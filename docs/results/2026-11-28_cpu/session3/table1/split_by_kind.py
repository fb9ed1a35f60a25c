import json
import sys

import numpy as np

r = json.load(open(sys.argv[1]))
for src, ents in r["entries"].items():
    rows = {}
    for e in ents:
        m = e.get("metrics", {}).get("photo")
        if not m or "3d-sdn" not in m or "2d" not in m:
            continue
        var = e["key"].split()[0].split("/")[1]
        for key in (var, e.get("edit_kind", "?"), "all"):
            rows.setdefault(key, []).append(m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"])
    for k, v in sorted(rows.items()):
        v = np.array(v)
        print(f"{src:9s} {k:18s} n={len(v):3d} 3D-2D PSNR(all) {v.mean():+.2f}  wins {int((v > 0).sum())}/{len(v)}")
