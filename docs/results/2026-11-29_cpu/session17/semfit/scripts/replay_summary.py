# ruff: noqa: E501, E701, E702
"""replay_summary.py REPLAY.json...: replay.py's summary line of each of its json files (every fitted vehicle proposal
of a tuning tree against its true car, an oracle for scoring: yaw 20-90 deg off, end-for-end flips, lengths off,
median |log| length and distance ratios, template right), and their total per variant (the file name's part after
the seed)."""
import json
import os
import sys
from collections import defaultdict

import numpy as np

pooled = defaultdict(list)
for f in sys.argv[1:]:
    rows = json.load(open(f)); name = os.path.basename(f)[:-5]
    pooled[name.split("_", 1)[1]] += rows
for label, rows in [(os.path.basename(f)[:-5], json.load(open(f))) for f in sys.argv[1:]] + [(f"ALL {k}", v) for k, v in pooled.items()]:
    ye = np.array([abs(r["yaw_err"]) for r in rows]); lr = np.array([r["len_ratio"] / r["dist_ratio"] for r in rows])
    dr = np.array([r["dist_ratio"] for r in rows]); tp = np.array([r["tpl"][0] == r["tpl"][1] for r in rows])
    print(f"{label:18s} n {len(rows):3d} yaw 20-90 {int(((ye > 20) & (ye <= 90)).sum()):3d} flip {int((ye > 90).sum()):3d} median |yaw| {np.median(ye):5.1f} "
          f"length off {int(((lr < 0.87) | (lr > 1.15)).sum()):3d} median |log len| {np.median(abs(np.log(lr))):.3f} median |log dist| {np.median(abs(np.log(dr))):.3f} template {tp.mean():.2f}")
