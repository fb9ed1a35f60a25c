# ruff: noqa: E501, E701, E702
"""pose_paired.py LABEL MAIN.json:BRANCH.json [...]: replay.py's cars of two codes (the same captured masks; matched by
source frame and instance id), pooled over the pairs: per code n, flips (> 90 degrees off) and their share, cars 30-90
off, median and 90th percentile of the yaw error; then branch minus main per car: the flip indicator (negative = fewer
flips) and the yaw error (degrees; negative = better), mean, 10k-draw paired bootstrap 95 % interval (seed 0) and
cars better/worse: session 13 rotloss's paired.py's ci()."""
import json
import sys

import numpy as np

PAIRED = "/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py"
ns: dict = {}
exec(compile(open(PAIRED).read().split("\nlabel, pairs")[0], PAIRED, "exec"), ns)
ci = ns["ci"]
label, pairs = sys.argv[1], [p.split(":") for p in sys.argv[2:]]
a, b = [], []
for fa, fb in pairs:
    ca = {(c["src"], c["id"]): c for c in json.load(open(fa))["cars"]}
    cb = {(c["src"], c["id"]): c for c in json.load(open(fb))["cars"]}
    for k in sorted(set(ca) & set(cb)):
        a.append(ca[k]["err"]); b.append(cb[k]["err"])
a, b = np.array(a), np.array(b)
print(f"== {label}: {len(a)} cars paired")
for name, e in (("main", a), ("branch", b)):
    print(f"  {name:6}: flips {int((e > 90).sum())} ({100 * (e > 90).mean():.1f} %), 30-90 {int(((e > 30) & (e <= 90)).sum())}, median {np.median(e):.1f}, p90 {np.percentile(e, 90):.1f}")
print(f"  branch - main, flip indicator: {ci(list((b > 90).astype(float) - (a > 90).astype(float)))} (wins = more flips)")
print(f"  branch - main, yaw error (deg): {ci(list(b - a))} (wins = larger error)")
