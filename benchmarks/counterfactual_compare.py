"""Paired comparison of two counterfactual-benchmark runs on the same pairs (e.g. a new photo appearance against
today's): per source scene, bin, method and metric, ``new - old`` over the pairs both scored, with the paired bootstrap
interval and wins/losses/ties (sdn3d.evaluation.paired). Besides the bins, the turns of :data:`POOLED_FROM_DEG` degrees
and more are pooled (bin ``turn >= 45``: the angles where a car shows sides the photo never saw). The intervals
resample whole cars, as the benchmark's own do (a parked car's pairs in every frame, variation and angle are one
piece of evidence); ``groups`` in each row is how many cars. Prints JSON, or a Markdown table with ``--markdown``.

    .venv/bin/python benchmarks/counterfactual_compare.py OLD/counterfactual.json NEW/counterfactual.json \\
        [--method photo:auto] [--markdown]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from sdn3d.evaluation.counterfactual import HIGHER_IS_BETTER, SOURCE_LABELS
from sdn3d.evaluation.paired import paired_difference

#: Turns of at least this many degrees are also pooled into one bin.
POOLED_FROM_DEG = 45.0


def _values(report: dict, name: str) -> dict:
    """``{(source, bin, method, 'region.metric', pair key): (value, car)}`` of a ``counterfactual.json`` (``name``:
    which one, for the error).

    Raises:
        ValueError: a pair has no ``car`` (a report written before the benchmark named each pair's car).
    """
    out = {}
    for p in report["pairs"]:
        if "car" not in p:
            raise ValueError(f"{name}: pair {p.get('key')!r} names no car (a counterfactual.json written before "
                             "sdn3d-bench recorded each pair's car; run the benchmark again)")
        for method, regions in p["metrics"].items():
            for region, metrics in regions.items():
                for metric, v in metrics.items():
                    if isinstance(v, (int, float)) and math.isfinite(v):
                        out[(p["source"], p["bin"], method, f"{region}.{metric}", p["key"])] = (float(v), p["car"])
    return out


def _pooled_bin(bin_: str) -> str | None:
    if not bin_.startswith("turn "):
        return None
    return f"turn >= {POOLED_FROM_DEG:g}" if abs(float(bin_.split()[1])) >= POOLED_FROM_DEG else None


def compare(old: dict, new: dict, methods: list[str] | None = None) -> list[dict]:
    """Rows ``{source, bin, method, column, **PairedDifference.to_dict()}``: ``new - old`` per bin and pooled."""
    a, b = _values(old, "old"), _values(new, "new")
    groups: dict[tuple, list[tuple[float, float, str]]] = {}
    for key, (v, car) in b.items():
        if key in a and (methods is None or key[2] in methods):
            groups.setdefault(key[:4], []).append((v, a[key][0], car))
            pooled = _pooled_bin(key[1])
            if pooled is not None:
                groups.setdefault((key[0], pooled, *key[2:4]), []).append((v, a[key][0], car))
    rows = []
    for (source, bin_, method, column), pairs in sorted(groups.items()):
        metric = column.split(".", 1)[1]
        if metric == "darkening":  # signed: compared through darkening_error
            continue
        d = paired_difference([x for x, _, _ in pairs], [y for _, y, _ in pairs],
                              higher_is_better=metric in HIGHER_IS_BETTER, groups=[c for _, _, c in pairs])
        rows.append({"source": source, "bin": bin_, "method": method, "column": column, **d.to_dict()})
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--method", action="append", help="only these methods (repeatable); default all")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args(argv)
    try:
        rows = compare(json.loads(args.old.read_text()), json.loads(args.new.read_text()), args.method)
    except ValueError as e:
        print(f"counterfactual_compare: error: {e}".replace("old:", f"{args.old}:").replace("new:", f"{args.new}:"),
              file=sys.stderr)
        return 2
    if not args.markdown:
        print(json.dumps({"old": str(args.old), "new": str(args.new), "rows": rows}, indent=1))
        return 0
    print(f"new `{args.new}` - old `{args.old}` over the same pairs: mean [95 % interval] wins/losses/ties, verdict\n")
    print("| source scene | bin | method | metric | n (cars) | new - old | verdict |\n|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {SOURCE_LABELS.get(r['source'], r['source'])} | {r['bin']} | {r['method']} | {r['column']} | "
              f"{r['n']} ({r['groups']}) | {r['mean']:+.4f} [{r['low']:+.4f}, {r['high']:+.4f}] "
              f"{r['wins']}/{r['losses']}/{r['ties']} | {r['verdict']} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
