# ruff: noqa: E501
"""paired.py OURS/counterfactual.json BASE/counterfactual.json [METHOD]: ours against base (sdn3d-bench counterfactual
outputs on the same pairs), per source scene and bin (turn angle, delete), for METHOD (default photo:rays): mean of
each, paired difference ours - base (10k bootstrap resamples, 95 % interval) and wins/losses/ties, on the car's
target pixels for turns (PSNR, L1, flat share) and on the vacated region plus shadow band for deletes (PSNR, L1,
darkening error)."""

from __future__ import annotations

import json
import sys
from collections import defaultdict

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "gt": "ground-truth masks (oracle)", "semantic": "predicted"}
METRICS = {"turn": (("car", "psnr", True), ("car", "l1", False), ("car", "flat", False)),
           "delete": (("hole", "psnr", True), ("hole", "l1", False), ("hole", "darkening_error", False))}


def rows(path: str, method: str) -> dict:
    out = {}
    for p in json.load(open(path))["pairs"]:
        if method in p["metrics"]:
            out[(p["source"], p["key"])] = p
    return out


ours, base = rows(sys.argv[1], sys.argv[3] if len(sys.argv) > 3 else "photo:rays"), rows(sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else "photo:rays")
method = sys.argv[3] if len(sys.argv) > 3 else "photo:rays"
groups = defaultdict(list)
for key in sorted(set(ours) & set(base)):
    groups[(key[0], ours[key]["bin"])].append(key)
print(f"ours: {sys.argv[1]}\nbase: {sys.argv[2]}\nmethod: {method}\n")
print("| source scene | bin | n | metric | base | ours | ours - base [95 % CI] | wins/losses/ties |")
print("|---|---|---|---|---|---|---|---|")
for (source, bin_), keys in sorted(groups.items()):
    kind = ours[keys[0]]["kind"]
    for region, metric, higher in METRICS[kind]:
        def value(p, region=region, metric=metric):
            return p["metrics"][method].get(region, {}).get(metric)
        pairs = [(value(ours[k]), value(base[k])) for k in keys]
        pairs = [(a, b) for a, b in pairs if a is not None and b is not None and a == a and b == b]
        if not pairs:
            continue
        a, b = zip(*pairs, strict=True)
        d = paired_difference(a, b, higher)
        print(f"| {LABELS.get(source, source)} | {bin_} | {d.n} | {region} {metric} | {sum(b) / len(b):.4f} | {sum(a) / len(a):.4f} | {d.mean:+.4f} [{d.low:+.4f}, {d.high:+.4f}] | {d.wins}/{d.losses}/{d.ties} |")
