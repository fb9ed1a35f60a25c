"""Session 22 side2: branch against main on counterfactual turn pairs (sdn3d-bench counterfactual.json, fill rays):
per tree, source scene and angle bin, the car target pixels' PSNR (mean of each code, paired difference branch - main
with its 10,000-resample bootstrap 95 % interval, wins/losses/ties) and the pairs that differ. The branch's values
are those of its runs given (whole trees, or the targets ``rules.py`` found changed, run with $KEYS); every other
pair takes main's value: its cars' paint decisions are main's (rules.py), so its pictures are main's.

    PYTHONPATH=src /work/main/.venv/bin/python compare.py LABEL MAIN_DIR BRANCH_DIR[,BRANCH_DIR...] [LABEL ...]
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict
from pathlib import Path

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "semantic": "predicted"}
FILL = "photo:rays"


def load(path: str) -> dict:
    file = Path(path) / "counterfactual.json"
    if not file.is_file():
        return {}
    pairs = json.loads(file.read_text())["pairs"]
    return {(p["source"], p["bin"], p["key"]): p["metrics"][FILL]["car"]["psnr"] for p in pairs
            if FILL in p["metrics"]}


def rows(label: str, main: dict, branch: dict) -> tuple[list[str], list[str]]:
    groups = defaultdict(list)
    for key in sorted(main):
        groups[key[:2]].append(key)
    out, differ = [], []
    for (source, bin_), keys in sorted(groups.items(), key=lambda g: (g[0][0], int(g[0][1].split()[-1]))):
        a = [branch.get(k, main[k]) for k in keys]
        b = [main[k] for k in keys]
        d = paired_difference(a, b, True)
        out.append(f"| {label} | {LABELS.get(source, source)} | {bin_} | {d.n} | {sum(b) / len(b):.3f} | "
                   f"{sum(a) / len(a):.3f} | {d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}] | "
                   f"{d.wins}/{d.losses}/{d.ties} |")
        differ += [f"{label} {LABELS.get(source, source)} {k[2]}: main {main[k]:.3f} branch {branch[k]:.3f} "
                   f"({branch[k] - main[k]:+.3f})" for k in keys if k in branch and branch[k] != main[k]]
    return out, differ


def main() -> int:
    args = sys.argv[1:]
    print("| tree | source scene | bin | n | car PSNR main | branch | branch - main [95 %] | wins/losses/ties |")
    print("|---|---|---|---|---|---|---|---|")
    notes = []
    for i in range(0, len(args), 3):
        branch: dict = {}
        for path in args[i + 2].split(","):
            branch.update(load(path))
        table, differ = rows(args[i], load(args[i + 1]), branch)
        print("\n".join(table))
        notes += differ
    print("\nPairs that differ:\n" + ("\n".join(f"- {n}" for n in notes) if notes else "- none"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
