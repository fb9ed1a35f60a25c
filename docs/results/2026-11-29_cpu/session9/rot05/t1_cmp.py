# ruff: noqa: E402, E501, E701, E702
"""t1_cmp.py BASE_RESULTS NEW_RESULTS: Table 1's 3D-SDN (photo) PSNR per region, new - base, paired per entry (the
bench's results.json); mean, 10k paired bootstrap 95 % interval, new better / worse entries."""
import json
import sys

import numpy as np


def load(p):
    out = {}
    for scene, entries in json.load(open(p))["entries"].items():
        for e in entries:
            m = e.get("metrics", {}).get("photo", {}).get("3d-sdn")
            if not m: continue
            for region in ("all", "largest", "objects"):
                if region in m and m[region].get("psnr") is not None and np.isfinite(m[region]["psnr"]):
                    out[(scene, region, e["index"])] = m[region]["psnr"]
    return out


a, b = load(sys.argv[1]), load(sys.argv[2])
rng = np.random.default_rng(0)
print("| scene | region | n | base PSNR | new PSNR | new - base [95 % CI] | new better / worse |")
print("|---|---|---|---|---|---|---|")
for scene, region in sorted({k[:2] for k in a}):
    ks = sorted(k for k in a if k[:2] == (scene, region) and k in b)
    d = np.array([b[k] - a[k] for k in ks])
    boots = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    print(f"| {scene} | {region} | {len(ks)} | {np.mean([a[k] for k in ks]):.3f} | {np.mean([b[k] for k in ks]):.3f} | {d.mean():+.5f} [{np.percentile(boots, 2.5):+.5f}, {np.percentile(boots, 97.5):+.5f}] | {int((d > 1e-9).sum())} / {int((d < -1e-9).sum())} |")
