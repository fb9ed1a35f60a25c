# ruff: noqa: E402, E501, E701, E702
"""paired.py LABEL MAIN_DIR BRANCH_DIR [LABEL MAIN_DIR BRANCH_DIR ...]: branch against main on the same counterfactual
turn pairs (sdn3d-bench counterfactual.json of each run, fill rays), on the car's target pixels: per label, source
scene and angle bin, then each source scene's bins pooled over every label given and its turns of 45 degrees and
more pooled: n, mean PSNR of each, the paired difference branch - main (sdn3d.evaluation.paired, 4000 bootstrap
resamples, 95 %) with wins/losses/ties, the same for L1 (lower is better), and the flat-colour share of each.
Session 30: each interval twice, resampling whole cars (groups = the physical car, world and instance id: its frames
and both variations, the rule's) and, beside it in braces, resampling pairs (last session's, deciding nothing)."""
from __future__ import annotations

import json
import sys
from collections import defaultdict

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "semantic": "predicted"}
FILL = "photo:rays"


def load(path: str) -> dict:
    return {(p["source"], p["bin"], p["key"]): p for p in json.load(open(f"{path}/counterfactual.json"))["pairs"]
            if p["kind"] == "turn" and FILL in p["metrics"]}


def car_of(key: str) -> tuple[str, str]:
    """The physical car ``(world, instance id)`` of a turn pair's key (``WORLD/VARIATION/FRAME ... car_ID ...``)."""
    return key.split("/")[0], key.split()[0].split("_")[-1]


def row(label, source, bin_, got):
    pm, pb = [g[0]["psnr"] for g in got], [g[1]["psnr"] for g in got]
    lm, lb = [g[0]["l1"] for g in got], [g[1]["l1"] for g in got]
    fm, fb = [g[0]["flat"] for g in got], [g[1]["flat"] for g in got]
    cars = [car_of(g[2]) for g in got]
    d = paired_difference(pb, pm, True, groups=cars)
    e = paired_difference(lb, lm, False, groups=cars)
    dp = paired_difference(pb, pm, True)
    ep = paired_difference(lb, lm, False)
    n = len(got)
    return (f"| {label} | {LABELS.get(source, source)} | {bin_} | {n} | {sum(pm) / n:.3f} | {sum(pb) / n:.3f} | "
            f"**{d.mean:+.3f}** [{d.low:+.3f}, {d.high:+.3f}] {{{dp.low:+.3f}, {dp.high:+.3f}}} | {d.groups or n} | {d.wins}/{d.losses}/{d.ties} | {sum(lm) / n:.4f} | {sum(lb) / n:.4f} | "
            f"{e.mean:+.4f} [{e.low:+.4f}, {e.high:+.4f}] {{{ep.low:+.4f}, {ep.high:+.4f}}} | {e.wins}/{e.losses}/{e.ties} | {100 * sum(fm) / n:.2f} | {100 * sum(fb) / n:.2f} |")


def main() -> int:
    args = sys.argv[1:]
    print("| tree | source scene | bin | n | PSNR main | PSNR branch | branch - main dB [95 % cars] {95 % pairs} | cars | w/l/t | L1 main | L1 branch "
          "| L1 branch - main [95 % cars] {95 % pairs} | w/l/t (lower better) | flat % main | flat % branch |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    pooled = defaultdict(list)
    labels = []
    for i in range(0, len(args), 3):
        label, main, branch = args[i], load(args[i + 1]), load(args[i + 2])
        labels.append(label)
        groups = defaultdict(list)
        for k in sorted(set(main) & set(branch)):
            groups[(k[0], k[1])].append((main[k]["metrics"][FILL]["car"], branch[k]["metrics"][FILL]["car"], f"{label}:{k[2]}"))
        for (source, bin_), got in sorted(groups.items(), key=lambda t: (t[0][0], int(t[0][1].split()[-1]))):
            print(row(label, source, bin_, got))
            pooled[(source, bin_)] += got
            if int(bin_.split()[-1]) >= 45:
                pooled[(source, "turn >= 45")] += got
    if len(labels) > 1:
        for (source, bin_), got in sorted(pooled.items(), key=lambda t: (t[0][0], t[0][1])):
            print(row(" + ".join(labels), source, bin_, got))
    else:
        for (source, bin_), got in pooled.items():
            if bin_ == "turn >= 45":
                print(row(labels[0], source, bin_, got))
    return 0


if __name__ == "__main__":
    sys.exit(main())
