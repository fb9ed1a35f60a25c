"""Paired comparison of two counterfactual-benchmark runs on the same pairs (e.g. a new photo appearance against
today's): per source scene, bin, method and metric, ``new - old`` over the pairs both scored, with the paired bootstrap
interval and wins/losses/ties (sdn3d.evaluation.paired). Prints JSON, or a Markdown table with ``--markdown``.

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


def _values(report: dict) -> dict:
    """``{(source, bin, method, 'region.metric', pair key): value}`` of a ``counterfactual.json``."""
    out = {}
    for p in report["pairs"]:
        for method, regions in p["metrics"].items():
            for region, metrics in regions.items():
                for metric, v in metrics.items():
                    if isinstance(v, (int, float)) and math.isfinite(v):
                        out[(p["source"], p["bin"], method, f"{region}.{metric}", p["key"])] = float(v)
    return out


def compare(old: dict, new: dict, methods: list[str] | None = None) -> list[dict]:
    a, b = _values(old), _values(new)
    groups: dict[tuple, list[tuple[float, float]]] = {}
    for key, v in b.items():
        if key in a and (methods is None or key[2] in methods):
            groups.setdefault(key[:4], []).append((v, a[key]))
    rows = []
    for (source, bin_, method, column), pairs in sorted(groups.items()):
        metric = column.split(".", 1)[1]
        if metric == "darkening":  # signed: compared through darkening_error
            continue
        d = paired_difference([x for x, _ in pairs], [y for _, y in pairs], higher_is_better=metric in HIGHER_IS_BETTER)
        rows.append({"source": source, "bin": bin_, "method": method, "column": column, **d.to_dict()})
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old", type=Path)
    parser.add_argument("new", type=Path)
    parser.add_argument("--method", action="append", help="only these methods (repeatable); default all")
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args(argv)
    rows = compare(json.loads(args.old.read_text()), json.loads(args.new.read_text()), args.method)
    if not args.markdown:
        print(json.dumps({"old": str(args.old), "new": str(args.new), "rows": rows}, indent=1))
        return 0
    print(f"new `{args.new}` - old `{args.old}` over the same pairs: mean [95 % interval] wins/losses/ties, verdict\n")
    print("| source scene | bin | method | metric | n | new - old | verdict |\n|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {SOURCE_LABELS.get(r['source'], r['source'])} | {r['bin']} | {r['method']} | {r['column']} | "
              f"{r['n']} | {r['mean']:+.4f} [{r['low']:+.4f}, {r['high']:+.4f}] {r['wins']}/{r['losses']}/"
              f"{r['ties']} | {r['verdict']} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
