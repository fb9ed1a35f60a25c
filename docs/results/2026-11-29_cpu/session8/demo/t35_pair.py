# ruff: noqa: E501
"""Session 7's and session 8's demo weights on the first 40 entries of the tuning-seed-35 benchmark tree
(/tmp/s6data/lead/t1_35), predicted row, photo mode: each one's 3D-SDN - 2D, and session 8's minus session 7's
3D-SDN and 2D values, paired over the entries both evaluated (sdn3d.evaluation.paired, 95 % bootstrap).

usage: python t35_pair.py S7_RESULTS_DIR S8_RESULTS_DIR
"""

from __future__ import annotations

import json
import math
import sys

from sdn3d.evaluation.paired import paired_difference

COLUMNS = [("psnr", "all", True), ("l1", "all", False), ("ssim", "all", True), ("psnr", "objects", True)]


def values(path: str) -> dict:
    rows = json.load(open(f"{path}/results.json"))["entries"]["semantic"]
    return {r["index"]: (r["metrics"] or {}).get("photo", {}) for r in rows}


def main(a: str, b: str) -> None:
    va, vb = values(a), values(b)
    print("| column | session 7 weights: 3D-SDN - 2D | session 8 weights: 3D-SDN - 2D | 3D-SDN: session 8 - session 7 | 2D: session 8 - session 7 |")
    print("|---|---|---|---|---|")
    for metric, region, hib in COLUMNS:
        cells = []
        for v in (va, vb):
            pairs = [(m["3d-sdn"][region][metric], m["2d"][region][metric]) for m in v.values()
                     if m and region in m.get("3d-sdn", {}) and region in m.get("2d", {})]
            ours, theirs = zip(*[p for p in pairs if all(math.isfinite(x) for x in p)], strict=True)
            d = paired_difference(ours, theirs, hib)
            cells.append(f"{d.mean:+.4g} [{d.low:+.4g}, {d.high:+.4g}], {d.wins}/{d.losses} of {d.n}")
        for method in ("3d-sdn", "2d"):
            keys = [k for k in va if va[k] and vb.get(k) and region in va[k].get(method, {}) and region in vb[k].get(method, {})
                    and math.isfinite(va[k][method][region][metric]) and math.isfinite(vb[k][method][region][metric])]
            d = paired_difference([vb[k][method][region][metric] for k in keys], [va[k][method][region][metric] for k in keys], hib)
            cells.append(f"{d.mean:+.4g} [{d.low:+.4g}, {d.high:+.4g}], {d.wins}/{d.losses} of {d.n}")
        print(f"| {metric.upper() if metric != 'ssim' else 'SSIM'} ({region}) | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
