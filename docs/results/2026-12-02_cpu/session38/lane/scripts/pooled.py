# ruff: noqa: INP001, E501
"""pooled.py DIR SEEDS ARMS: pose_table rows pooled over the held-out trees (DIR/pose_{seed}_{arm}.json): per row and
arm, the matched objects' median / p90 yaw error, the share over 20 degrees, flips over 90 (unmatched counted as
flipped), the median distance error (x1e-2) and template accuracy, with a 95 % bootstrap interval of the median yaw
error (resampling cars, 2000 draws, seed 0); and whether each row's records are identical between the arms."""
import json
import sys

import numpy as np

DIR, SEEDS, ARMS = sys.argv[1], sys.argv[2].split(","), sys.argv[3].split(",")
rows = {}
for arm in ARMS:
    for s in SEEDS:
        for row, objs in json.load(open(f"{DIR}/pose_{s}_{arm}.json"))["objects"].items():
            rows.setdefault(row, {}).setdefault(arm, []).extend(objs)
rng = np.random.default_rng(0)
for row, arms in rows.items():
    print(f"## {row}")
    for arm, objs in arms.items():
        m = [o for o in objs if o.get("matched", True)]
        y = np.array([o["yaw_deg"] for o in m])
        boot = np.median(y[rng.integers(0, len(y), (2000, len(y)))], axis=1)
        print(f"{arm:5s} cars {len(objs)} matched {len(m)}: yaw median {np.median(y):.2f} [{np.percentile(boot, 2.5):.2f}, "
              f"{np.percentile(boot, 97.5):.2f}] p90 {np.percentile(y, 90):.1f}, over 20 deg {np.mean(y > 20):.3f}, "
              f"flips {np.mean([o['yaw_deg'] > 90 for o in objs]):.3f}, distance median {100 * np.median([o['dist'] for o in m]):.1f}, "
              f"template acc {np.mean([o['template_ok'] for o in m]):.3f}")
    a, b = (arms.get(x) for x in ARMS[:2])
    if a is not None and b is not None:
        same = len(a) == len(b) and all(x["yaw_deg"] == y["yaw_deg"] and x["dist"] == y["dist"] for x, y in zip(a, b, strict=True))
        print(f"identical between {ARMS[0]} and {ARMS[1]}: {same}")
