# ruff: noqa: E402, E501, E701, E702
"""Paired differences on the deletes of counterfactual.json files (sdn3d.evaluation.paired: mean, 95 % bootstrap
interval, wins/losses/ties): this branch's photo:rays against every other method of this branch's run and of the
main's run (774bffb) on the same pairs, plus the darkening left in the shadow band (session 5).

usage: paired3.py NEW/counterfactual.json MAIN/counterfactual.json [NAME]
"""

import json
import sys

from sdn3d.evaluation.paired import paired_difference


def deletes(path):
    return {p["key"]: p for p in json.load(open(path))["pairs"] if p["kind"] == "delete" and p["metrics"]}


new, base = deletes(sys.argv[1]), deletes(sys.argv[2])
name = sys.argv[3] if len(sys.argv) > 3 else "data"
keys = sorted(set(new) & set(base))
ref = [new[k]["metrics"]["photo:rays"]["hole"] for k in keys]
print(f"n = {len(keys)} deletes; reference: this branch's photo:rays\n")
print("| data | rays vs | PSNR other | ΔPSNR dB | ΔL1 | Δdarkening error |\n|---|---|---|---|---|---|")
others = [("this branch", m, new) for m in ("photo:auto", "photo:patchmatch", "photo:telea", "generator", "2d")] + [
    ("main", m, base) for m in ("photo:auto", "photo:patchmatch", "photo:telea", "generator", "photo:rays", "2d")]
for who, method, run in others:
    if method not in run[keys[0]]["metrics"]:
        continue
    other = [run[k]["metrics"][method]["hole"] for k in keys]
    cells = []
    for metric, hib, digits in (("psnr", True, 2), ("l1", False, 4), ("darkening_error", False, 3)):
        d = paired_difference([r[metric] for r in ref], [o[metric] for o in other], higher_is_better=hib)
        cells.append(f"{d.mean:+.{digits}f} [{d.low:+.{digits}f}, {d.high:+.{digits}f}] {d.wins}/{d.losses}/{d.ties}")
    mean = sum(o["psnr"] for o in other) / len(other)
    print(f"| {name} | {who} {method} | {mean:.2f} | " + " | ".join(cells) + " |")
mean = lambda xs: sum(xs) / len(xs)  # noqa: E731
print(f"\nthis branch's rays: PSNR {mean([r['psnr'] for r in ref]):.2f} dB, residual darkening "
      f"{mean([r['darkening'] for r in ref]):.3f} (target's {mean([new[k]['reference']['target'] for k in keys]):.3f}, "
      f"input's {mean([new[k]['reference']['source'] for k in keys]):.3f})")
