"""turns.py LABEL MAIN_DIR BRANCH_DIR [LABEL MAIN_DIR BRANCH_DIR ...]: branch against main on the same counterfactual
turn pairs (sdn3d-bench counterfactual.json of each run, fill rays; session 21 side's table with L1 and the changed
pixels added): per tree (label; labels repeated pool their trees), source scene and angle bin, the car's target pixels'
PSNR (mean of each code, paired difference branch - main with its 10,000-resample bootstrap 95 % interval,
wins/losses/ties), their L1 (paired difference, lower is better), the changed pixels' PSNR (the car's target pixels,
the vacated ones and the shadow band: everything an edit changes; outside them both codes draw the input) and the
car's share of flat colour (mean of each; the paired difference, lower is better).

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session23/front/turns.py \\
        cf31 /tmp/s23data/front/bench/main_cf31_oracle /tmp/s23data/front/bench/branch_cf31_oracle ...
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
    pairs = json.loads((Path(path) / "counterfactual.json").read_text())["pairs"]
    # the tree's run in the key: pair keys repeat between trees of the same worlds, and labels may pool trees
    return {(p["source"], p["bin"], f"{path}|{p['key']}"): p["metrics"][FILL] for p in pairs if FILL in p["metrics"]}


def interval(d) -> str:
    return f"{d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}]"


def rows(label: str, main: dict, branch: dict) -> list[str]:
    groups = defaultdict(list)
    for key in sorted(set(main) & set(branch)):
        groups[key[:2]].append(key)
    out = []
    for (source, bin_), keys in sorted(groups.items(), key=lambda g: (g[0][0], int(g[0][1].split()[-1]))):
        a, b = [branch[k]["car"]["psnr"] for k in keys], [main[k]["car"]["psnr"] for k in keys]
        d = paired_difference(a, b, True)
        la, lb = [branch[k]["car"]["l1"] for k in keys], [main[k]["car"]["l1"] for k in keys]
        ld = paired_difference(la, lb, False)
        ca, cb = [branch[k]["changed"]["psnr"] for k in keys], [main[k]["changed"]["psnr"] for k in keys]
        cd = paired_difference(ca, cb, True)
        fa, fb = [branch[k]["car"]["flat"] for k in keys], [main[k]["car"]["flat"] for k in keys]
        f = paired_difference(fa, fb, False)
        out.append(f"| {label} | {LABELS.get(source, source)} | {bin_} | {d.n} | {sum(b) / len(b):.3f} | "
                   f"{sum(a) / len(a):.3f} | {interval(d)} | {d.wins}/{d.losses}/{d.ties} | "
                   f"{1000 * ld.mean:+.2f} [{1000 * ld.low:+.2f}, {1000 * ld.high:+.2f}] | {interval(cd)} | "
                   f"{sum(fb) / len(fb):.4f} | {sum(fa) / len(fa):.4f} | {f.mean:+.4f} |")
    return out


def main() -> int:
    args = sys.argv[1:]
    print("| tree | source scene | bin | n | car PSNR main | branch | branch - main [95 %] | wins/losses/ties "
          "| car L1 x1000 branch - main [95 %] (lower better) | changed pixels PSNR branch - main [95 %] "
          "| flat share main | branch | branch - main |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    merged: dict[str, tuple[dict, dict]] = {}
    for i in range(0, len(args), 3):
        main_, branch = merged.setdefault(args[i], ({}, {}))
        main_.update(load(args[i + 1]))
        branch.update({(k[0], k[1], k[2].replace(args[i + 2], args[i + 1], 1)): v
                       for k, v in load(args[i + 2]).items()})
    for label, (main_, branch) in merged.items():
        print("\n".join(rows(label, main_, branch)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
