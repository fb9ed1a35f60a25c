# ruff: noqa: E501
"""pooled.py NEW1.json:BASE1.json [NEW2.json:BASE2.json ...]: sdn3d-bench counterfactual=true outputs (photo:rays),
pairs pooled over the trees (keyed by tree and pair): per source scene and turn bin, mean car-pixel PSNR of base (main)
and new (branch), the paired difference (10k bootstrap resamples, 95 %, seed 0), wins/losses/ties, the L1 difference
(positive: new lower) and the flat-colour share of both."""

from __future__ import annotations

import json
import sys

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "semantic": "predicted"}
BINS = ("turn 15", "turn 45", "turn 90", "turn 180")


def load(path: str, tree: int) -> dict:
    out = {}
    for p in json.load(open(path))["pairs"]:
        car = p["metrics"].get("photo:rays", {}).get("car")
        if car and car.get("psnr") is not None:
            out[(p["source"], p["bin"], tree, p["key"])] = (car["psnr"], car["l1"], car.get("flat", float("nan")))
    return out


def main() -> None:
    new, base = {}, {}
    for tree, arg in enumerate(sys.argv[1:]):
        n, b = arg.split(":")
        new |= load(n, tree)
        base |= load(b, tree)
    print("files: " + ", ".join(sys.argv[1:]) + "\n")
    print("| source scene | bin | n | PSNR main | PSNR branch | difference [95 % CI] | wins/losses/ties | L1 difference (positive: branch lower) [95 % CI] | flat share main / branch |")
    print("|---|---|---|---|---|---|---|---|---|")
    for source in ("oracle", "semantic"):
        for bin_ in BINS:
            keys = sorted(k for k in new if k in base and k[0] == source and k[1] == bin_)
            if not keys:
                continue
            a, b = [new[k] for k in keys], [base[k] for k in keys]
            d = paired_difference([x[0] for x in a], [x[0] for x in b], True, samples=10000)
            l1 = paired_difference([x[1] for x in a], [x[1] for x in b], False, samples=10000)
            print(f"| {LABELS[source]} | {bin_} | {d.n} | {sum(x[0] for x in b) / len(b):.2f} | {sum(x[0] for x in a) / len(a):.2f} | "
                  f"{d.mean:+.3f} [{d.low:+.3f}, {d.high:+.3f}] | {d.wins}/{d.losses}/{d.ties} | {-l1.mean:+.4f} [{-l1.high:+.4f}, {-l1.low:+.4f}] | "
                  f"{100 * sum(x[2] for x in b) / len(b):.1f} % / {100 * sum(x[2] for x in a) / len(a):.1f} % |")


if __name__ == "__main__":
    main()
