"""paired_kinds.py JSON...: photo_latency.py --against runs (columns ``this:rays`` and ``session_start:rays``), edit by
edit: for all edits and for each kind, the median CPU and wall ms of each code and the geometric mean of the per-edit
ratio this / session_start with a 10,000-resample paired bootstrap 95 % interval (seed 0), and the wins / losses
(edits this code drew in less / more time)."""

import json
import sys

import numpy as np

rows = []
for path in sys.argv[1:]:
    d = json.load(open(path))
    rows += [(a[0], a[1], a[2], b[1], b[2]) for a, b in zip(d["this:rays"], d["session_start:rays"], strict=True)]
print(f"{len(sys.argv) - 1} runs, {len(rows)} paired edits")
print("| measure | kind | edits | this median ms | session start median ms | this / start [95 %] | wins / losses |")
print("|---|---|---|---|---|---|---|")
for col, name in ((2, "CPU"), (1, "wall")):
    for kind in ["all"] + sorted({r[0] for r in rows}):
        sel = [r for r in rows if kind == "all" or r[0] == kind]
        a, b = np.array([r[col] for r in sel]), np.array([r[col + 2] for r in sel])
        logs = np.log(a / b)
        rng = np.random.default_rng(0)
        boots = np.exp(np.array([logs[rng.integers(0, len(logs), len(logs))].mean() for _ in range(10000)]))
        lo, hi = np.percentile(boots, [2.5, 97.5])
        print(f"| {name} | {kind} | {len(sel)} | {np.median(a):.0f} | {np.median(b):.0f} | "
              f"{np.exp(logs.mean()):.3f} [{lo:.3f}, {hi:.3f}] | {(a < b).sum()} / {(a > b).sum()} |")
