# ruff: noqa: E501, INP001
"""arms.py RES OUT.md SEEDS ARMS: Table 1 photo rows per arm (RES/{seed}_{arm}/results.json from rows.sh), pooled
over the seeds' trees, per kind (rotate, zoom): 3D-SDN minus the 2D paste on PSNR all, L1 all, PSNR objects (95 %
interval, sdn3d.evaluation.paired.paired_difference, resampling cars joined across entries, session 33's rule),
and each arm's gain against the first arm's, paired by entry (the same entries: only the proposals differ).
SEEDS and ARMS are comma-separated."""
import json
import math
import os
import sys

import numpy as np

from sdn3d.evaluation.paired import paired_difference

RES, OUT, SEEDS, ARMS = sys.argv[1], sys.argv[2], sys.argv[3].split(","), sys.argv[4].split(",")
COLS = (("psnr", "all"), ("l1", "all"), ("psnr", "objects"))


def joined(recs):  # entries sharing a car are one group (union-find over results.json's `cars`)
    parent = {r["index"]: r["index"] for r in recs}

    def find(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k
    owner = {}
    for r in recs:
        for c in [repr(c) for c in (r.get("cars") or [])]:
            if c in owner:
                parent[find(r["index"])] = find(owner[c])
            else:
                owner[c] = r["index"]
    return {r["index"]: find(r["index"]) for r in recs}


data = {}  # (arm, seed, index) -> {kind, group, 3d-sdn: {col}, 2d: {col}}
for seed in SEEDS:
    for arm in ARMS:
        (recs,) = json.load(open(os.path.join(RES, f"{seed}_{arm}", "results.json")))["entries"].values()
        grp = joined(recs)
        for r in recs:
            m = (r.get("metrics") or {}).get("photo") or {}
            if m:
                data[(arm, seed, r["index"])] = {"kind": r["edit_kind"], "group": f"{seed}:{grp[r['index']]}", **{
                    meth: {f"{k}/{g}": m.get(meth, {}).get(g, {}).get(k, float("nan")) for k, g in COLS} for meth in ("3d-sdn", "2d")}}


def sd(x, k):
    return f"{x:+.2f}" if k == "psnr" else f"{x:+.4f}"


lines = [f"Trees {SEEDS}; arms {ARMS}; rows: predicted (semantic proposals), photo appearance, 312x96.", "",
         "| arm | kind | column | n (car groups) | 3D-SDN / 2D | 3D-SDN - 2D [95 %, cars joined] wins/losses | gain - first arm's gain [95 %, paired by entry] |",
         "|---|---|---|---|---|---|---|"]
for kind in ("rotate", "zoom"):
    for arm in ARMS:
        for k, g in COLS:
            c, hib = f"{k}/{g}", k == "psnr"
            keys = [(s, i) for (a, s, i), e in data.items() if a == arm and e["kind"] == kind
                    and all(math.isfinite(e[m][c]) for m in ("3d-sdn", "2d"))]
            if not keys:
                continue
            es = [data[(arm, s, i)] for s, i in keys]
            d = paired_difference([e["3d-sdn"][c] for e in es], [e["2d"][c] for e in es], higher_is_better=hib, groups=[e["group"] for e in es])
            vs = "-"
            base = ARMS[0]
            pk = [(s, i) for s, i in keys if (base, s, i) in data and math.isfinite(data[(base, s, i)]["3d-sdn"][c]) and math.isfinite(data[(base, s, i)]["2d"][c])]
            if arm != base and pk:
                ga = [data[(arm, s, i)]["3d-sdn"][c] - data[(arm, s, i)]["2d"][c] for s, i in pk]
                gb = [data[(base, s, i)]["3d-sdn"][c] - data[(base, s, i)]["2d"][c] for s, i in pk]
                v = paired_difference(ga, gb, higher_is_better=hib, groups=[data[(arm, s, i)]["group"] for s, i in pk])
                vs = f"{sd(v.mean, k)} [{sd(v.low, k)}, {sd(v.high, k)}] (n {len(pk)})"
            f3, f2 = np.mean([e["3d-sdn"][c] for e in es]), np.mean([e["2d"][c] for e in es])
            fm = (lambda x: f"{x:.2f}") if hib else (lambda x: f"{x:.4f}")
            bold = (d.low > 0) if hib else (d.high < 0)
            cell = f"{sd(d.mean, k)} [{sd(d.low, k)}, {sd(d.high, k)}] {d.wins}/{d.losses}"
            lines.append(f"| {arm} | {kind} | {c} | {len(es)} ({len(set(e['group'] for e in es))}) | {fm(f3)} / {fm(f2)} | {'**' + cell + '**' if bold else cell} | {vs} |")
open(OUT, "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
