# ruff: noqa: E501, E701, E702
"""pose_table.py LABEL:POSES.json[,POSES.json...] ...: the pose of every edited (modified) object of Table 1 runs
against its ground-truth car (session 13 rotloss's poses.py json; an oracle, for scoring only), one line per label:
operations with a fitted pose, those whose proposal overlaps its car at IoU >= 0.3, yaw 20-90 deg off, end-for-end
flips (> 90), median |yaw error|, template right, median length ratio / distance ratio, length off (that ratio outside
[0.87, 1.15], causes.py's rule), median |log distance ratio|."""
import json
import sys

import numpy as np

print(f"{'label':34s} {'ops':>4s} {'iou>=.3':>7s} {'yaw 20-90':>9s} {'flip>90':>7s} {'med|yaw|':>8s} {'template':>8s} {'len/dist med':>12s} {'len off':>7s} {'med|log d|':>10s}")
for arg in sys.argv[1:]:
    label, files = arg.split(":", 1)
    ops = [o for f in files.split(",") for r in json.load(open(f)) for o in r["ops"] if o["type"] == "modify" and "yaw_err" in o]
    sel = [o for o in ops if o["mask_iou"] >= 0.3]
    ye = np.array([abs(o["yaw_err"]) for o in sel]); lr = np.array([o["len_ratio"] / o["dist_ratio"] for o in sel])
    dr = np.array([o["dist_ratio"] for o in sel]); tp = np.array([o["tpl"][0] == o["tpl"][1] for o in sel])
    print(f"{label:34s} {len(ops):4d} {len(sel):7d} {int(((ye > 20) & (ye <= 90)).sum()):9d} {int((ye > 90).sum()):7d} {np.median(ye):8.1f} {tp.mean():8.2f} {np.median(lr):12.2f} {int(((lr < 0.87) | (lr > 1.15)).sum()):7d} {np.median(np.abs(np.log(dr))):10.3f}")
