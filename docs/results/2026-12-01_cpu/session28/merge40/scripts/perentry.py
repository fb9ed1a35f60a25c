"""perentry.py RUN [RUN...]: per entry of Table 1 photo runs (results.json of dbench.py / sdn3d-bench), its kind and
3D-SDN minus the 2D paste on PSNR and L1 (signed: positive = 3D-SDN better) of 'all', and the pooled mean per kind
(delete and occluder_removed) with its 10k paired bootstrap 95 % interval (seed 0) and wins/losses."""
import json
import os
import sys

import numpy as np


def ci(d: list[float]) -> str:
    a = np.asarray([x for x in d if np.isfinite(x)])
    if not len(a):
        return "n=0"
    boot = a[np.random.default_rng(0).integers(0, len(a), (10000, len(a)))].mean(1)
    return (f"{a.mean():+.3f} [{np.percentile(boot, 2.5):+.3f}, {np.percentile(boot, 97.5):+.3f}] "
            f"{int((a > 1e-9).sum())}/{int((a < -1e-9).sum())} (n {len(a)})")


def rows(run: str) -> list[tuple[str, int, str, float, float]]:
    out = []
    for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]:
        m = (e.get("metrics") or {}).get("photo") or {}
        if "3d-sdn" in m and "2d" in m:
            s, b = m["3d-sdn"]["all"], m["2d"]["all"]
            out.append((e["edit_kind"], e["index"], e["key"], s["psnr"] - b["psnr"], b["l1"] - s["l1"]))
    return out


if __name__ == "__main__":
    pooled: dict[str, list] = {}
    for run in sys.argv[1:]:
        for kind, index, key, dp, dl in rows(run):
            print(f"{os.path.basename(run):22s} {index:4d} {kind:16s} {key:28s} dPSNR {dp:+.3f} dL1 {dl:+.4f}")
            pooled.setdefault(kind, []).append((dp, dl))
    for kind, vals in sorted(pooled.items()):
        print(f"== {kind}: PSNR all 3D-2D {ci([v[0] for v in vals])} | L1 all {ci([v[1] for v in vals])}")
