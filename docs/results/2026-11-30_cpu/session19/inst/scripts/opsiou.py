# ruff: noqa: E501, E701, E702, E731, B007, B023, B905
"""opsiou.py MAIN_RUN:BRANCH_RUN [...]: per Table 1 semantic row (session 11 dbench.py runs: RUN.dump/<entry>.npz holds
the picks, the composed source proposals and the ground-truth instance ids of the edited cars, an oracle used for
scoring only), each operation's picked proposal's IoU with its true car, and whether any proposal of the source
reaches IoU >= 0.3 / >= 0.5 with that car (a pick rule could take it). Counts per arm, pooled over the pairs."""
import glob
import os
import sys

import numpy as np


def ops(run):
    out = {}
    for f in sorted(glob.glob(f"{run}.dump/*.npz")):
        z = np.load(f); i = int(os.path.basename(f)[:4]); P = z["proposals"]; ids = [p for p in np.unique(P) if p > 0]
        for k, (p, g) in enumerate(zip(z["picks"].tolist(), z["gt_ids"].tolist())):
            S = z["src_inst"] == g
            iou = lambda q: float((P == q)[S].sum()) / max(float(((P == q) | S).sum()), 1.0)
            out[(i, k)] = (iou(p), max([iou(q) for q in ids] or [0.0]))
    return out


tot = {}
for pair in sys.argv[1:]:
    a, b = (ops(r) for r in pair.split(":"))
    keys = sorted(set(a) & set(b))
    for arm, d in (("main", a), ("branch", b)):
        c = tot.setdefault(arm, [0] * 6)
        row = [len(keys), sum(d[k][0] < 0.3 for k in keys), sum(d[k][0] >= 0.5 for k in keys),
               sum(d[k][1] < 0.3 for k in keys), sum(d[k][1] >= 0.5 for k in keys), sum(d[k][0] < 0.3 and d[k][1] >= 0.3 for k in keys)]
        for j, v in enumerate(row): c[j] += v
        print(f"{os.path.basename(pair.split(':')[0 if arm == 'main' else 1]):18s} operations {row[0]}: pick IoU < 0.3: {row[1]}, pick IoU >= 0.5: {row[2]}; no proposal >= 0.3 on the car: {row[3]}, some proposal >= 0.5: {row[4]}; pick < 0.3 though one >= 0.3 exists: {row[5]}")
for arm, row in tot.items():
    print(f"pooled {arm:11s} operations {row[0]}: pick IoU < 0.3: {row[1]}, pick IoU >= 0.5: {row[2]}; no proposal >= 0.3 on the car: {row[3]}, some proposal >= 0.5: {row[4]}; pick < 0.3 though one >= 0.3 exists: {row[5]}")
