# ruff: noqa: E501
"""fills.py BRANCH/counterfactual.json MAIN/counterfactual.json: each fill of the branch's run (photo:rays,
photo:learnt) against each of the issue's original fills in main's run (photo:telea, photo:patchmatch, and
photo:generator / generator:* where the run had it) on the same delete pairs, per source scene: mean PSNR on the vacated
region plus shadow band of each, paired difference branch - original (10k bootstrap resamples, 95 % interval) and
wins/losses/ties; then the best original fill by mean per source, and the residual darkening of each fill (the
benchmark's hole darkening: the band's darkening against the road ring, mean) next to the truth's and the input's."""

from __future__ import annotations

import json
import sys
from collections import defaultdict

from sdn3d.evaluation.paired import paired_difference

LABELS = {"oracle": "ground-truth geometry (oracle)", "gt": "ground-truth masks (oracle)", "semantic": "predicted"}


def by_key(path: str) -> dict:
    return {(p["source"], p["key"]): p for p in json.load(open(path))["pairs"] if p["kind"] == "delete"}


ours, base = by_key(sys.argv[1]), by_key(sys.argv[2])
keys = sorted(set(ours) & set(base))
sources = sorted({k[0] for k in keys})
originals = sorted({m for k in keys for m in base[k]["metrics"] if m in ("photo:telea", "photo:patchmatch") or "generator" in m})
print(f"branch: {sys.argv[1]}\nmain: {sys.argv[2]}\n")
print("| source scene | branch fill | original fill | n | PSNR original | PSNR branch | branch - original [95 % CI] | wins/losses/ties |")
print("|---|---|---|---|---|---|---|---|")
for source in sources:
    ks = [k for k in keys if k[0] == source]
    means = defaultdict(float)
    for fill in ("photo:rays", "photo:learnt"):
        for orig in originals:
            pairs = [(ours[k]["metrics"].get(fill, {}).get("hole", {}).get("psnr"), base[k]["metrics"].get(orig, {}).get("hole", {}).get("psnr")) for k in ks]
            pairs = [(a, b) for a, b in pairs if a is not None and b is not None]
            if not pairs:
                continue
            a, b = zip(*pairs, strict=True)
            d = paired_difference(a, b, True)
            means[orig] = sum(b) / len(b)
            print(f"| {LABELS.get(source, source)} | {fill} | {orig} | {d.n} | {sum(b) / len(b):.2f} | {sum(a) / len(a):.2f} | {d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] | {d.wins}/{d.losses}/{d.ties} |")
    if means:
        best = max(means, key=means.get)
        print(f"| {LABELS.get(source, source)} | best original by mean: {best} ({means[best]:.2f} dB) | | | | | | |")
print("\n| source scene | fill | n | residual darkening, mean (branch) | the truth's (exact render without the car) | the input's (the car's shadow there) | darkening error, mean (branch) |")
print("|---|---|---|---|---|---|---|")
for source in sources:
    ks = [k for k in keys if k[0] == source]
    for fill in ("photo:rays", "photo:learnt"):
        vals = [ours[k]["metrics"].get(fill, {}).get("hole", {}) for k in ks]
        vals = [v for v in vals if v.get("darkening") is not None]
        if vals:
            refs = [ours[k]["reference"] for k in ks if ours[k]["metrics"].get(fill, {}).get("hole", {}).get("darkening") is not None]
            print(f"| {LABELS.get(source, source)} | {fill} | {len(vals)} | {sum(v['darkening'] for v in vals) / len(vals):+.4f} | {sum(r['target'] for r in refs) / len(refs):+.4f} | {sum(r['source'] for r in refs) / len(refs):+.4f} | {sum(v['darkening_error'] for v in vals) / len(vals):.4f} |")
