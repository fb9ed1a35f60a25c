# ruff: noqa: E501, E702
"""zpair.py BASE.json NEW.json: replay.py outputs of the same captures, paired per fitted proposal (matched to the same
ground-truth car, oracle): per weather, cut (mask stops >= 2 px above the car's visible bottom) or not, the signed median
relative distance error, and the change of |error| (capped at 1): mean, 95 % paired bootstrap interval (10k, seed 0),
proposals nearer the truth / farther (by more than 0.01)."""
import json
import sys

import numpy as np

a = {(x["key"], x["row"]): x for x in json.load(open(sys.argv[1]))}
b = {(x["key"], x["row"]): x for x in json.load(open(sys.argv[2]))}
ks = [k for k in a if k in b]
rng = np.random.default_rng(0)
for var in ("clone", "rain", "all"):
    for name, f in (("cut", lambda x: x["cut"] >= 2), ("uncut", lambda x: x["cut"] < 2), ("all", lambda x: True)):
        s = [k for k in ks if (var == "all" or a[k]["var"] == var) and f(a[k])]
        if not s:
            continue
        za = np.array([a[k]["z_err"] for k in s]); zb = np.array([b[k]["z_err"] for k in s])
        d = np.abs(zb).clip(0, 1) - np.abs(za).clip(0, 1)
        boot = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
        lo, hi = np.percentile(boot, [2.5, 97.5])
        print(f"{var:5s} {name:5s} n {len(s):3d}: signed median {np.median(za):+.3f} -> {np.median(zb):+.3f}; |err| change {d.mean():+.3f} [{lo:+.3f}, {hi:+.3f}] nearer/farther {int((d < -0.01).sum())}/{int((d > 0.01).sum())}")
