"""Paired comparison of two codes' per-edit times from benchmarks/photo_latency.py --against ... --json FILE: per edit
the ratio this/other of the CPU ms and of the wall ms, their geometric mean with a paired bootstrap 95 % interval
(10k resamples of the edits), and wins (this cheaper) / losses.

    python paired_latency.py FILE.json [THIS OTHER]   # default: this:rays main:rays
"""

import json
import sys

import numpy as np

data = json.load(open(sys.argv[1]))
this, other = (sys.argv[2], sys.argv[3]) if len(sys.argv) > 3 else ("this:rays", "main:rays")
a, b = np.array([e[1:] for e in data[this]]), np.array([e[1:] for e in data[other]])
kinds = [e[0] for e in data[this]]
rng = np.random.default_rng(0)
print(f"{len(a)} edits, {this} against {other}")
for col, name in ((1, "CPU"), (0, "wall")):
    log = np.log(a[:, col] / b[:, col])
    boot = np.exp(log[rng.integers(0, len(log), (10000, len(log)))].mean(1))
    lo, hi = np.percentile(boot, [2.5, 97.5])
    wins, losses = int((a[:, col] < b[:, col]).sum()), int((a[:, col] > b[:, col]).sum())
    print(f"{name}: ratio (geometric mean) {np.exp(log.mean()):.3f} [95 % {lo:.3f}, {hi:.3f}], median ms "
          f"{np.median(a[:, col]):.0f} vs {np.median(b[:, col]):.0f}, wins {wins} losses {losses}")
    for kind in sorted(set(kinds)):
        k = np.array([x == kind for x in kinds])
        print(f"  {kind}: ratio {np.exp(log[k].mean()):.3f} over {int(k.sum())} edits, median ms "
              f"{np.median(a[k, col]):.0f} vs {np.median(b[k, col]):.0f}")
