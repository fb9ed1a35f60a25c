"""Two demo benchmarks' predicted rows (bench/results.json, entries['semantic']), entry by entry: for each method and
the photo mode's regions all / largest / objects, the mean of AFTER minus BEFORE, its paired-bootstrap 95 % interval
(10k resamples, seed 0) and on how many entries AFTER was better / worse. Usage: python paired_rows.py BEFORE AFTER"""
# ruff: noqa: T201
from __future__ import annotations

import json
import sys

import numpy as np

LOWER_BETTER = {"l1"}


def main(before: str, after: str) -> None:
    b = {e["key"]: e for e in json.load(open(before))["entries"]["semantic"]}
    a = {e["key"]: e for e in json.load(open(after))["entries"]["semantic"]}
    keys = sorted(set(a) & set(b))
    print(f"{len(keys)} entries in both ({len(a)} after, {len(b)} before)")
    rng = np.random.default_rng(0)
    print("| method | column | after - before [95 % interval] | after better / worse (entries) |")
    print("|---|---|---|---|")
    for method in ("3d-sdn", "2d"):
        for region in ("all", "largest", "objects"):
            for metric in ("l1", "ssim", "psnr"):
                pairs = [(a[k]["metrics"]["photo"][method][region][metric], b[k]["metrics"]["photo"][method][region]
                          [metric]) for k in keys if a[k]["metrics"].get("photo", {}).get(method, {}).get(region)
                         and b[k]["metrics"].get("photo", {}).get(method, {}).get(region)]
                pairs = [(x, y) for x, y in pairs if x is not None and y is not None and x == x and y == y]
                d = np.array([x - y for x, y in pairs])
                if not len(d):
                    continue
                boot = d[rng.integers(0, len(d), (10_000, len(d)))].mean(1)
                lo, hi = np.percentile(boot, [2.5, 97.5])
                sign = -1 if metric in LOWER_BETTER else 1
                better, worse = int((sign * d > 0).sum()), int((sign * d < 0).sum())
                print(f"| {method} | {metric} ({region}) | {d.mean():+.4f} [{lo:+.4f}, {hi:+.4f}] | {better} / {worse} "
                      f"of {len(d)} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
