"""Paired table of ``benchmarks/edit_call.py`` runs: this branch (mode ``run``) against main (tree ``main``).

    python paired_calls.py RUN.json [RUN.json ...] > table.md

The calls of one run alternate (main, branch, main, ...), so call i of each is a pair made at the same load. Per file,
and pooled where a thread count has several files: medians, min-max, the paired differences branch - main (mean,
10,000-resample bootstrap 95 % interval of the mean), the geometric-mean ratio branch / main with its bootstrap
interval, and wins (branch faster) / losses.
"""

from __future__ import annotations

import json
import random
import statistics
import sys
from pathlib import Path


def _boot(values: list[float], stat, resamples: int = 10000, seed: int = 0) -> tuple[float, float]:
    rng = random.Random(seed)
    n = len(values)
    draws = sorted(stat([values[rng.randrange(n)] for _ in range(n)]) for _ in range(resamples))
    return draws[int(0.025 * resamples)], draws[int(0.975 * resamples) - 1]


def _geo(ratios: list[float]) -> float:
    return statistics.geometric_mean(ratios)


def _row(label: str, branch: list[float], main: list[float]) -> str:
    diffs = [b - m for b, m in zip(branch, main, strict=True)]
    ratios = [b / m for b, m in zip(branch, main, strict=True)]
    lo, hi = _boot(diffs, statistics.fmean)
    rlo, rhi = _boot(ratios, _geo)
    wins = sum(d < 0 for d in diffs)
    return (f"| {label} | {len(diffs)} | {statistics.median(branch):.3f} ({min(branch):.2f}-{max(branch):.2f}) | "
            f"{statistics.median(main):.3f} ({min(main):.2f}-{max(main):.2f}) | {statistics.fmean(diffs):+.3f} "
            f"[{lo:+.3f}, {hi:+.3f}] | {_geo(ratios):.3f} [{rlo:.3f}, {rhi:.3f}] | {wins} / {len(diffs) - wins} |")


def main() -> None:
    print("| run, measure | pairs | branch median s (min-max) | main median s (min-max) | branch - main s, mean "
          "[95 %] | branch / main, geometric mean [95 %] | wins / losses |")
    print("|---|---|---|---|---|---|---|")
    pooled: dict[str, tuple[list[float], list[float]]] = {}
    files: dict[str, int] = {}
    for path in sys.argv[1:]:
        report = json.loads(Path(path).read_text())
        name = f"{Path(path).stem} (threads {report['threads']}, load {report['load_average_before'][0]:.1f}"\
               f"->{report['load_average_after'][0]:.1f})"
        for measure in ("wall_s", "cpu_s"):
            branch = report["modes"]["run"][measure]["values"]
            main_ = report["modes"]["main"][measure]["values"]
            print(_row(f"{name}, {measure[:-2]}", branch, main_))
            key = f"threads {report['threads']}, {measure[:-2]}"
            files[key] = files.get(key, 0) + 1
            b, m = pooled.setdefault(key, ([], []))
            b.extend(branch)
            m.extend(main_)
    for key, (b, m) in pooled.items():
        if files[key] > 1:
            print(_row(f"pooled, {key}", b, m))


if __name__ == "__main__":
    main()
