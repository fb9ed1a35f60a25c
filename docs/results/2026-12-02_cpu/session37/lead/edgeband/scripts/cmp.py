# ruff: noqa: INP001, E501
"""cmp.py A.json B.json: pose_table's pred_fit rows of two runs, paired by (frame, car): matched cars' median / p90
yaw error, flips (over 90 degrees; unmatched counted as flipped), fixed / broken flips, median distance and length
error, template accuracy, and the share of cars whose yaw error is over 20 degrees."""
import json
import sys

import numpy as np


def load(p):
    return {(o["frame"], o["id"]): o for o in json.load(open(p))["objects"]["fit, predicted proposals"]}


a, b = load(sys.argv[1]), load(sys.argv[2])
keys = sorted(set(a) & set(b))
for name, d in (("A", a), ("B", b)):
    m = [d[k] for k in keys if d[k].get("matched", True)]
    yaw = np.array([o["yaw_deg"] for o in m])
    print(f"{name}: {len(keys)} cars, matched {len(m)}: yaw median {np.median(yaw):.2f} p90 {np.percentile(yaw, 90):.1f}, "
          f"over 20 deg {np.mean(yaw > 20):.3f}, flips (unmatched counted) {sum(1 for k in keys if d[k]['yaw_deg'] > 90)}, "
          f"distance median {np.median([o['dist'] for o in m]):.3f}, length median {np.median([o['length'] for o in m]):.3f}, "
          f"template acc {np.mean([o['template_ok'] for o in m]):.3f}")
fixed = sum(1 for k in keys if a[k]["yaw_deg"] > 90 >= b[k]["yaw_deg"])
broken = sum(1 for k in keys if b[k]["yaw_deg"] > 90 >= a[k]["yaw_deg"])
both = [k for k in keys if a[k].get("matched", True) and b[k].get("matched", True)]
d = np.array([b[k]["yaw_deg"] - a[k]["yaw_deg"] for k in both])
print(f"B against A: flips fixed {fixed}, broken {broken}; matched in both {len(both)}: yaw error better by over 5 deg "
      f"{int((d < -5).sum())}, worse by over 5 deg {int((d > 5).sum())}")
