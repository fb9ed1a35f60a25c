"""Paired bootstrap of micro.py's per-edit times: per function, the geometric mean over the edits that call it of
this branch's ms over main's (10k resamples of those edits, 95 %), wins / losses and the mean saving per edit.

    python micro_paired.py measured/micro.txt
"""

import re
import sys
from collections import defaultdict

import numpy as np

per: dict[str, list[tuple[float, float]]] = defaultdict(list)
for line in open(sys.argv[1]):
    if line.startswith("edit "):
        for name, new, old in re.findall(r"(_\w+) ([\d.]+) vs ([\d.]+)", line):
            if float(old) > 0:
                per[name].append((float(new), float(old)))
rng = np.random.default_rng(0)
for name, pairs in sorted(per.items()):
    new, old = np.array(pairs).T
    log = np.log(new / old)
    boot = np.exp(log[rng.integers(0, len(log), (10000, len(log)))].mean(1))
    low, high = np.quantile(boot, [0.025, 0.975])
    print(f"{name}: {len(log)} edits calling it, new/main {np.exp(log.mean()):.3f} [95 % {low:.3f}, {high:.3f}], "
          f"wins {int((new < old).sum())} losses {int((new > old).sum())}, mean saving {np.mean(old - new):.1f} ms "
          f"per edit that calls it ({np.sum(old - new) / 14:.1f} over all 14)")
