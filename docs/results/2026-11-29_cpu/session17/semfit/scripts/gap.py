# ruff: noqa: E501, E701, E702
"""gap.py LABEL BASE_RUN:NEW_RUN [...]: Table 1 rows pooled over pairs of runs (one pair per tree), per kind: the gap
3D-SDN minus the 2D paste of base and of new, and its change new minus base paired per entry (the merge rule's
measure), with 3D-SDN's and the 2D paste's own changes; PSNR all, L1 all (sign: positive = 3D-SDN / new better),
PSNR objects. Mean, 10k-draw paired bootstrap 95 % interval (seed 0), wins/losses (n). Session 13 rotloss's paired.py
reads the runs."""
import importlib.util
import os
import sys

spec = importlib.util.spec_from_file_location("paired_rows", "/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py")
paired_src = open(spec.origin).read().split("\nlabel, pairs")[0]  # its load() and ci() only
ns = {}; exec(compile(paired_src, spec.origin, "exec"), ns)
load, ci = ns["load"], ns["ci"]
label, pairs = sys.argv[1], [p.split(":") for p in sys.argv[2:]]
rows = []
for b, n in pairs:
    a, c = load(b), load(n)
    rows += [(a[i], c[i]) for i in sorted(set(a) & set(c))]
print(f"== {label}: {len(rows)} entries; base {', '.join(os.path.basename(p[0]) for p in pairs)}; new {', '.join(os.path.basename(p[1]) for p in pairs)}")
for metric, region, sign in (("psnr", "all", 1), ("l1", "all", -1), ("psnr", "objects", 1)):
    print(f"-- {metric} {region}" + (" (sign: positive = 3D-SDN / new better)" if sign < 0 else ""))
    for kind in ["ALL"] + sorted({r[0][0] for r in rows}):
        sel = [r for r in rows if (kind == "ALL" or r[0][0] == kind) and region in r[0][2] and region in r[1][2]]
        if not sel: continue
        gb = [sign * (r[0][2][region][metric] - r[0][3][region][metric]) for r in sel]
        gn = [sign * (r[1][2][region][metric] - r[1][3][region][metric]) for r in sel]
        print(f"{kind:16s} gap change new-base {ci([y - x for x, y in zip(gb, gn, strict=True)])} | 3D-2D base {ci(gb)} | new {ci(gn)}"
              f" | 3D new-base {ci([sign * (r[1][2][region][metric] - r[0][2][region][metric]) for r in sel])}"
              f" | 2D new-base {ci([sign * (r[1][3][region][metric] - r[0][3][region][metric]) for r in sel])}")
