# ruff: noqa: E501
"""Per-bin turn table of counterfactual benchmark runs (issue 41's "Turns" goals): car PSNR per run (mean [95 %
bootstrap interval]), paired differences (final - main, final - issue-time, the 2D paste - final) with wins/losses,
the goal (final at least 2 dB over the issue-time run) and the flat-colour share.

    python turns_table.py SOURCE issue=ISSUE/counterfactual.json main=MAIN/counterfactual.json \
        final=FINAL/counterfactual.json [--title TITLE]

SOURCE: oracle | gt | semantic (the benchmark's source scene). A run may be left out (e.g. no issue-time run).
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from sdn3d.evaluation.paired import paired_difference

BINS = ("turn 15", "turn 45", "turn 90", "turn 180")


def _per_pair(report: dict, source: str, method: str, region: str, metric: str) -> dict[str, float]:
    out = {}
    for p in report["pairs"]:
        if p["source"] != source or p["kind"] != "turn":
            continue
        v = ((p.get("metrics") or {}).get(method) or {}).get(region, {}).get(metric)
        if isinstance(v, (int, float)) and math.isfinite(v):
            out[p["key"]] = float(v)
    return out


def _mean_ci(values: list[float], samples: int = 10000, seed: int = 0) -> str:
    a = np.asarray(values)
    if not len(a):
        return "–"
    rng = np.random.default_rng(seed)
    means = a[rng.integers(0, len(a), size=(samples, len(a)))].mean(1)
    lo, hi = np.quantile(means, [0.025, 0.975])
    return f"{a.mean():.2f} [{lo:.2f}, {hi:.2f}]"


def _diff(a: dict[str, float], b: dict[str, float], keys: list[str]) -> str:
    keys = [k for k in keys if k in a and k in b]
    if not keys:
        return "–"
    d = paired_difference([a[k] for k in keys], [b[k] for k in keys], higher_is_better=True)
    return f"{d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] {d.wins}/{d.losses}"


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("source")
    ap.add_argument("runs", nargs="+", help="label=path")
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    runs = {k: json.loads(open(v).read()) for k, v in (r.split("=", 1) for r in args.runs)}
    psnr = {k: _per_pair(r, args.source, "photo:auto", "car", "psnr") for k, r in runs.items()}
    flat = {k: _per_pair(r, args.source, "photo:auto", "car", "flat") for k, r in runs.items()}
    region = {k: _per_pair(r, args.source, "photo:auto", "changed", "psnr") for k, r in runs.items()}
    paste = {k: _per_pair(r, args.source, "2d", "car", "psnr") for k, r in runs.items()}
    labels = list(runs)
    lines = [f"## {args.title or args.source}: car PSNR (dB) on the turn pairs", ""]
    head = ["bin", "n"] + labels
    if "final" in runs and "main" in runs:
        head.append("final - main")
    if "final" in runs and "issue" in runs:
        head += ["final - issue", "goal: final >= issue + 2"]
    lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for b in BINS:
        keys = sorted({k for k in psnr[labels[0]] if k.endswith(b.replace("turn ", "turn_"))})
        row = [b, str(len(keys))] + [_mean_ci([psnr[k][x] for x in keys if x in psnr[k]]) for k in labels]
        if "final" in runs and "main" in runs:
            row.append(_diff(psnr["final"], psnr["main"], keys))
        if "final" in runs and "issue" in runs:
            row.append(_diff(psnr["final"], psnr["issue"], keys))
            common = [x for x in keys if x in psnr["final"] and x in psnr["issue"]]
            f = np.mean([psnr["final"][x] for x in common])
            i = np.mean([psnr["issue"][x] for x in common])
            row.append(("n/a (bin under 45)" if b == "turn 15" else ("met" if f >= i + 2 else "not met"))
                       + f" ({f:.2f} vs {i + 2:.2f})")
        lines.append("| " + " | ".join(row) + " |")
    lines += ["", "Flat colour (% of a turned car's pixels drawn as fallback or default colour), mean per pair:", ""]
    lines += ["| bin | " + " | ".join(labels) + " |", "|---|" + "---|" * len(labels)]
    for b in BINS:
        keys = sorted({k for k in flat[labels[0]] if k.endswith(b.replace("turn ", "turn_"))})
        lines.append(f"| {b} | " + " | ".join(
            f"{100 * np.mean([flat[k][x] for x in keys if x in flat[k]]):.1f}" if keys else "–" for k in labels) + " |")
    lines += ["", "Car + vacated + shadow region PSNR (the whole change), and the 2D paste minus each run's car PSNR:",
              ""]
    lines += ["| bin | " + " | ".join(f"region {k}" for k in labels) + " | "
              + " | ".join(f"2D paste - {k}" for k in labels) + " |", "|---|" + "---|" * (2 * len(labels))]
    for b in BINS:
        keys = sorted({k for k in psnr[labels[0]] if k.endswith(b.replace("turn ", "turn_"))})
        lines.append(f"| {b} | " + " | ".join(_mean_ci([region[k][x] for x in keys if x in region[k]])
                                               for k in labels) + " | "
                     + " | ".join(_diff(paste[k], psnr[k], keys) for k in labels) + " |")
    if "final" in runs and "main" in runs:
        lines += ["", "Region PSNR final - main: " + "; ".join(
            f"{b}: {_diff(region['final'], region['main'], sorted(k for k in region['final'] if k.endswith(b.replace('turn ', 'turn_'))))}"
            for b in BINS)]
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
