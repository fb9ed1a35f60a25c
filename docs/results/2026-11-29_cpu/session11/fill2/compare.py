# ruff: noqa: E501
"""compare.py NAME=SCORE.json [NAME=SCORE.json ...]: validation table of learnt-fill variants, fill step alone
(benchmarks/learnt_fill.py score --json; every file over the same pairs): per tree and pooled, rays' PSNR and each
variant's, each variant - rays and each variant - the first one (paired bootstrap 95 %, 10k resamples, w/l/t)."""
import json
import sys

from sdn3d.evaluation.paired import paired_difference

runs = {a.split("=")[0]: {r["key"]: r for r in json.load(open(a.split("=")[1]))} for a in sys.argv[1:]}
names = list(runs)
keys = sorted(set.intersection(*(set(r) for r in runs.values())))
trees = sorted({k.split(":")[0] for k in keys})
first = names[0]
mean = lambda xs: sum(xs) / len(xs)  # noqa: E731


def cell(a, b):
    d = paired_difference(a, b, higher_is_better=True)
    return f"{d.mean:+.2f} [{d.low:+.2f}, {d.high:+.2f}] {d.wins}/{d.losses}"


print("| tree (n) | rays dB | " + " | ".join(f"{n} dB" for n in names) + " | " + " | ".join(f"{n} - rays" for n in names) + " | " + " | ".join(f"{n} - {first}" for n in names[1:]) + " |")
print("|---" * (2 + 2 * len(names) + len(names) - 1) + "|")
for tree in [*trees, "pooled"]:
    ks = [k for k in keys if tree == "pooled" or k.split(":")[0] == tree]
    rays = [runs[first][k]["rays"]["psnr"] for k in ks]
    got = {n: [runs[n][k]["learnt"]["psnr"] for k in ks] for n in names}
    print(f"| {tree} ({len(ks)}) | {mean(rays):.2f} | " + " | ".join(f"{mean(got[n]):.2f}" for n in names) + " | "
          + " | ".join(cell(got[n], rays) for n in names) + " | " + " | ".join(cell(got[n], got[first]) for n in names[1:]) + " |")
