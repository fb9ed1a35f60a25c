"""cf_paired.py OUT.md LABEL MAIN_DIR BRANCH_DIR: the counterfactual benchmark's deletes (sdn3d-bench
counterfactual.json of cf_bench.sh runs, 624x192, the exact picture without the car as the truth), main against
the branch on the same pairs: the 2D paste's hole PSNR and L1 branch - main (L1 signed: positive = branch better),
and 3D-SDN (``photo:rays``) minus 2D on each code. Mean, 10,000-resample paired bootstrap 95 % interval (numpy
default_rng(0)), wins/losses (n).
Run: /work/main/.venv/bin/python cf_paired.py OUT.md "cf31, ground-truth geometry (oracle)" MAIN_DIR BRANCH_DIR
"""

from __future__ import annotations

import json
import os
import sys

import numpy as np

SDN, BASE = "photo:rays", "2d"


def load(path: str) -> dict[str, dict]:
    """``{pair key: metrics}`` of the pairs both methods scored."""
    pairs = json.load(open(f"{path}/counterfactual.json"))["pairs"]
    return {p["key"]: p["metrics"] for p in pairs if SDN in p["metrics"] and BASE in p["metrics"]}


def ci(d: list[float], digits: int) -> str:
    """Mean [95 % paired bootstrap] wins/losses (n)."""
    d = np.asarray(d)
    boot = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    lo, hi = np.percentile(boot, 2.5), np.percentile(boot, 97.5)
    return (f"{d.mean():+.{digits}f} [{lo:+.{digits}f}, {hi:+.{digits}f}] "
            f"{int((d > 1e-9).sum())}/{int((d < -1e-9).sum())} (n {len(d)})")


def main(out: str, label: str, main_dir: str, branch_dir: str) -> None:
    a, b = load(main_dir), load(branch_dir)
    keys = sorted(set(a) & set(b))
    lines = [f"# Counterfactual deletes, {label}: main vs branch, {len(keys)} pairs (hole = vacated + shadow band)", "",
             "| metric | 2D paste branch - main | 3D-SDN - 2D, main | 3D-SDN - 2D, branch | 3D-SDN equal |",
             "|---|---|---|---|---|"]
    for metric, sign, digits in (("psnr", 1, 3), ("l1", -1, 4)):
        d2 = [sign * (b[k][BASE]["hole"][metric] - a[k][BASE]["hole"][metric]) for k in keys]
        gap_a = [sign * (a[k][SDN]["hole"][metric] - a[k][BASE]["hole"][metric]) for k in keys]
        gap_b = [sign * (b[k][SDN]["hole"][metric] - b[k][BASE]["hole"][metric]) for k in keys]
        same = all(a[k][SDN] == b[k][SDN] for k in keys)
        lines.append(f"| {metric} | {ci(d2, digits)} | {ci(gap_a, digits)} | {ci(gap_b, digits)} | {same} |")
    text = "\n".join(lines) + "\n"
    tmp = f"{out}.tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, out)
    print(text)


if __name__ == "__main__":
    main(*sys.argv[1:5])
