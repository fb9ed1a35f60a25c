"""Paired figures of ab_call.py's JSON: per round, branch minus main (seconds) and branch / main, with a 10,000-resample
paired bootstrap 95 % interval of the mean, wins / losses (branch lower / higher), and the medians.

    python paired.py AB.json [AB.json ...] [--a main] [--b br]     (several files: their rounds pooled)
"""

from __future__ import annotations

import argparse
import json
import statistics

import numpy as np


def _interval(values: np.ndarray, rng: np.random.Generator) -> tuple[float, float]:
    means = values[rng.integers(0, len(values), size=(10_000, len(values)))].mean(1)
    return float(np.percentile(means, 2.5)), float(np.percentile(means, 97.5))


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("files", nargs="+")
    parser.add_argument("--a", default="main")
    parser.add_argument("--b", default="br")
    args = parser.parse_args()
    runs = {args.a: [], args.b: []}
    for f in args.files:
        data = json.load(open(f))
        for k in runs:
            runs[k] += data["runs"][k]
    rng = np.random.default_rng(0)
    print(f"{len(runs[args.a])} rounds; {args.b} against {args.a}")
    for what in ("cpu_s", "wall_s"):
        a = np.array([r[what] for r in runs[args.a]])
        b = np.array([r[what] for r in runs[args.b]])
        d, q = b - a, b / a
        lo, hi = _interval(d, rng)
        qlo, qhi = _interval(q, rng)
        print(f"{what}: {args.b} - {args.a} {d.mean():+.3f} s [{lo:+.3f}, {hi:+.3f}]; ratio {q.mean():.3f} "
              f"[{qlo:.3f}, {qhi:.3f}]; wins/losses {int((d < 0).sum())}/{int((d > 0).sum())}; medians "
              f"{statistics.median(b):.3f} vs {statistics.median(a):.3f} s")


if __name__ == "__main__":
    main()
