"""ab_kinds.py AB_OUTPUT: session 17 cost4's ab.py output (per edit: kind, least CPU ms of each arm) summarised per
kind: the geometric mean of new / main with a 10,000-resample paired bootstrap 95 % interval (seed 0) over that kind's
edits, wins / losses, and the median CPU ms of each arm."""

import re
import sys

import numpy as np

rows = [(m[1], float(m[2]), float(m[3])) for m in
        re.finditer(r"edit +\d+ (\S+) +new +([\d.]+) ms +main +([\d.]+) ms", open(sys.argv[1]).read())]
print("| kind | edits | new median ms | main median ms | new / main [95 %] | wins / losses |")
print("|---|---|---|---|---|---|")
for kind in ["all"] + sorted({r[0] for r in rows}):
    sel = [r for r in rows if kind == "all" or r[0] == kind]
    new, main = np.array([r[1] for r in sel]), np.array([r[2] for r in sel])
    logs = np.log(new / main)
    rng = np.random.default_rng(0)
    boots = np.exp(logs[rng.integers(0, len(logs), (10000, len(logs)))].mean(1))
    lo, hi = np.percentile(boots, [2.5, 97.5])
    print(f"| {kind} | {len(sel)} | {np.median(new):.0f} | {np.median(main):.0f} | {np.exp(logs.mean()):.3f} "
          f"[{lo:.3f}, {hi:.3f}] | {(new < main).sum()} / {(new > main).sum()} |")
