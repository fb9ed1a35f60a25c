# ruff: noqa: E501, E701, E702
"""variants.py DIAG_DIR TAG [TAG ...]: per row (semantic proposals, ground-truth masks (oracle)), the three tuning
trees' cars pooled (diag.py outputs DIAG_DIR/{semantic,gt}{35,37,31}_TAG.json; the first TAG is the reference,
main's fit), each variant's template accuracy beside the majority floor, flips (|yaw error| > 90 deg), median |yaw
error|, lengths off (length ratio over distance ratio outside [0.87, 1.15]), and its paired difference from the
reference in template accuracy: mean, 10k-draw bootstrap 95 % interval (seed 0), cars won/lost; also per tree."""
import json
import sys
from collections import Counter

import numpy as np


def ci(d):
    d = np.asarray(d, dtype=float)
    bt = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 0).sum())}/{int((d < 0).sum())}"


folder, tags = sys.argv[1], sys.argv[2:]
ROWS = {"semantic": "semantic proposals", "gt": "ground-truth masks (oracle)"}
for row, name in ROWS.items():
    for seeds in (("35", "37", "31"), ("35",), ("37",), ("31",)):
        load = {t: [c for s in seeds for c in json.load(open(f"{folder}/{row}{s}_{t}.json"))] for t in tags}
        ref = load[tags[0]]
        key = [(c["src"], c["id"]) for c in ref]
        truth = np.array([c["truth_tpl"] for c in ref]); n = len(ref)
        floor = Counter(truth.tolist()).most_common(1)[0][1] / n
        print(f"== {name}, tree(s) {'+'.join(seeds)}: {n} cars, majority floor {floor:.3f}")
        base = np.array([c["fit_tpl"] for c in ref]) == truth
        for t in tags:
            cs = load[t]
            assert [(c["src"], c["id"]) for c in cs] == key, t
            acc = np.array([c["fit_tpl"] for c in cs]) == truth
            ye = np.abs([c["yaw_err"] for c in cs]); lr = np.array([c["len_ratio"] / c["dist_ratio"] for c in cs])
            print(f"  {t:>12}: template {acc.mean():.3f}, flips {int((ye > 90).sum())} ({(ye > 90).mean():.3f}), median |yaw| {np.median(ye):.1f}, "
                  f"lengths off {int(((lr < 0.87) | (lr > 1.15)).sum())}; template minus {tags[0]}: {ci(acc.astype(float) - base)}")
