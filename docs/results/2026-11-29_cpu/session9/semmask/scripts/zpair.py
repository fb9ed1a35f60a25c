# ruff: noqa: E402, E501, E701, E702
"""zpair.py BASE_PREFIX NEW_PREFIX SEED...: per fitted semantic proposal (count.py's count_<PREFIX>_<SEED>.json), the
relative distance error |z_fit - z_true| / z_true (truth: the matched ground-truth object, an oracle used to measure),
capped at 1; paired new minus base: mean with a 10k bootstrap 95 % interval, wins/losses (0.02 dead band); for all
proposals and for those whose mask misses the car's bottom (>= max(2 px, 15 % of the truth's height))."""
import json
import sys

import numpy as np

b, n = sys.argv[1:3]; seeds = sys.argv[3:]
A, B, M = [], [], []
for s in seeds:
    x = {(r["key"], r["id"]): r for r in json.load(open(f"/tmp/s9data/semmask/count_{b}_{s}.json"))}
    y = {(r["key"], r["id"]): r for r in json.load(open(f"/tmp/s9data/semmask/count_{n}_{s}.json"))}
    for k in sorted(set(x) & set(y)):
        r = x[k]; A.append(min(abs(r["z_err"]), 1)); B.append(min(abs(y[k]["z_err"]), 1))
        M.append(r["gt_bottom"] - r["bottom"] >= max(2, 0.15 * (r["gt_bottom"] - r["gt_top"] + 1)))
A, B, M = map(np.asarray, (A, B, M))
rng = np.random.default_rng(0)
for name, sel in (("all", np.ones_like(M)), ("mask misses bottom", M), ("the rest", ~M)):
    d = (B - A)[sel]
    if not len(d): continue
    bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    print(f"{' '.join(seeds)} {name:19s} n {len(d):3d} |z err| base {A[sel].mean():.3f} new {B[sel].mean():.3f} (medians {np.median(A[sel]):.3f} -> {np.median(B[sel]):.3f}); new-base {d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] better/worse {int((d < -0.02).sum())}/{int((d > 0.02).sum())}")
