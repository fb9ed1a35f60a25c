"""turns.py LABEL MAIN_DIR BRANCH_DIR [LABEL MAIN_DIR BRANCH_DIR ...]: branch against main on the same counterfactual
turn pairs (sdn3d-bench counterfactual.json of each run, fill rays): per tree, source scene and angle bin, the car's
target pixels' PSNR (mean of each code, paired difference branch - main with its 10,000-resample bootstrap 95 %
interval, wins/losses/ties) and their share of flat colour (mean of each; the paired difference, lower is better).

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session21/side/turns.py \\
        cf31 /tmp/s21side/bench/main_cf31_oracle /tmp/s21side/bench/branch_cf31_oracle ...
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
    return {(p["source"], p["bin"], p["key"]): p["metrics"][FILL]["car"] for p in pairs if FILL in p["metrics"]}


def rows(label: str, main: dict, branch: dict) -> list[str]:
    groups = defaultdict(list)
    for key in sorted(set(main) & set(branch)):
        groups[key[:2]].append(key)
    out = []
    for (source, bin_), keys in sorted(groups.items(), key=lambda g: (g[0][0], int(g[0][1].split()[-1]))):
        a, b = [branch[k]["psnr"] for k in keys], [main[k]["psnr"] for k in keys]
        d = paired_difference(a, b, True)
        fa, fb = [branch[k]["flat"] for k in keys], [main[k]["flat"] for k in keys]
        f = paired_difference(fa, fb, False)
        out.append(f"| {label} | {LABELS.get(source, source)} | {bin_} | {d.n} | {sum(b) / len(b):.3f} | "
                   f"{sum(a) / len(a):.3f} | {d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}] | "
                   f"{d.wins}/{d.losses}/{d.ties} | "
                   f"{sum(fb) / len(fb):.4f} | {sum(fa) / len(fa):.4f} | {f.mean:+.4f} [{f.low:+.4f}, {f.high:+.4f}] |")
    return out


def main() -> int:
    args = sys.argv[1:]
    print("| tree | source scene | bin | n | car PSNR main | branch | branch - main [95 %] | wins/losses/ties "
          "| flat share main | branch | branch - main [95 %] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for i in range(0, len(args), 3):
        print("\n".join(rows(args[i], load(args[i + 1]), load(args[i + 2]))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
