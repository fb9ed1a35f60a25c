"""Paired differences of photo:rays against each other method on the deletes of counterfactual.json files
(sdn3d.evaluation.paired: mean, 95 % bootstrap interval, wins/losses/ties), per file and pooled.

usage: paired.py NAME=counterfactual.json [NAME=...]
"""

import json
import sys

from sdn3d.evaluation.paired import paired_difference

runs = dict(a.split("=", 1) for a in sys.argv[1:])
pooled: dict = {}
print("| data | rays vs | n | ΔPSNR dB | ΔL1 | Δdarkening error |\n|---|---|---|---|---|---|")
for name, path in list(runs.items()) + [("pooled", None)]:
    if path is not None:
        pairs = [p for p in json.load(open(path))["pairs"] if p["kind"] == "delete" and p["metrics"]]
    else:
        pairs = pooled["pairs"]
    pooled.setdefault("pairs", []).extend(pairs if path is not None else [])
    for other in ("photo:auto", "photo:patchmatch", "photo:telea", "generator", "2d"):
        if other not in pairs[0]["metrics"]:
            continue
        cells = []
        for metric, hib in (("psnr", True), ("l1", False), ("darkening_error", False)):
            a = [p["metrics"]["photo:rays"]["hole"][metric] for p in pairs]
            b = [p["metrics"][other]["hole"][metric] for p in pairs]
            d = paired_difference(a, b, higher_is_better=hib)
            digits = 2 if metric == "psnr" else 4 if metric == "l1" else 3
            cells.append(
                f"{d.mean:+.{digits}f} [{d.low:+.{digits}f}, {d.high:+.{digits}f}] {d.wins}/{d.losses}/{d.ties}"
            )
        print(f"| {name} | {other} | {len(pairs)} | " + " | ".join(cells) + " |")
