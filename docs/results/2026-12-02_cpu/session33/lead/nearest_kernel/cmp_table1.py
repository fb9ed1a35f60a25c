# ruff: noqa: E501
"""cmp_table1.py BEFORE AFTER: per-entry photo scores of two sdn3d-bench runs of the same tree: entries whose 3D-SDN
PSNR / L1 (all, objects) changed, and the largest change."""
import json
import math
import sys


def load(p):
    (recs,) = json.load(open(f"{p}/results.json"))["entries"].values()
    return {r["index"]: r for r in recs}
a, b = load(sys.argv[1]), load(sys.argv[2])
changed, biggest, n = 0, 0.0, 0
for i in a:
    ma = ((a[i].get("metrics") or {}).get("photo") or {}).get("3d-sdn")
    mb = ((b[i].get("metrics") or {}).get("photo") or {}).get("3d-sdn")
    if not ma or not mb:
        continue
    n += 1
    diffs = [abs(ma[r][k] - mb[r][k]) for r in ("all", "objects") for k in ("psnr", "l1") if r in ma and math.isfinite(ma[r][k]) and math.isfinite(mb[r][k])]
    d = max(diffs) if diffs else 0.0
    if d > 0:
        changed += 1
        if ma["all"]["psnr"] != mb["all"]["psnr"]:
            biggest = max(biggest, abs(ma["all"]["psnr"] - mb["all"]["psnr"]))
print(f"{n} entries scored in both; {changed} with any 3D-SDN score changed; largest PSNR (all) change {biggest:.4f} dB")
