"""step_threads.py's steps as 1-thread / 2-thread pairs (in the order they ran): the mean of 2-thread minus 1-thread
wall and CPU seconds, its paired-bootstrap 95 % interval (10k resamples, seed 0), how often 2 threads were faster /
slower, and what share of the machine other processes took. Usage: python paired_steps.py step_threads.json"""
# ruff: noqa: T201
from __future__ import annotations

import json
import sys

import numpy as np


def main(path: str) -> None:
    rows = json.load(open(path))
    one = [r for r in rows if r["threads"] == 1]
    two = [r for r in rows if r["threads"] == 2]
    rng = np.random.default_rng(0)
    for key in ("wall_s", "cpu_s"):
        d = np.array([b[key] - a[key] for a, b in zip(one, two, strict=True)])
        boot = d[rng.integers(0, len(d), (10_000, len(d)))].mean(1)
        lo, hi = np.percentile(boot, [2.5, 97.5])
        print(f"{key}: 1 thread mean {np.mean([a[key] for a in one]):.3f}, 2 threads mean "
              f"{np.mean([b[key] for b in two]):.3f}; 2 - 1 = {d.mean():+.3f} [{lo:+.3f}, {hi:+.3f}]; 2 threads "
              f"faster / slower in {int((d < 0).sum())} / {int((d > 0).sum())} of {len(d)} pairs")
    others = [r["others_cores"] for r in rows]
    print(f"other processes took {min(others):.2f}-{max(others):.2f} cores of 2 during the steps (median "
          f"{float(np.median(others)):.2f}); 1-minute load {min(r['load1'] for r in rows):.1f}-"
          f"{max(r['load1'] for r in rows):.1f}")


if __name__ == "__main__":
    main(sys.argv[1])
