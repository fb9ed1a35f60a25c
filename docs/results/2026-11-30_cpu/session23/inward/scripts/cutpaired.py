"""cutpaired.py ROW MAIN.json:BRANCH.json [...]: two codes' pose tables (benchmarks/pose_table.py --out) on the same
trees, paired per car (frame and instance id; pred_fit: the cars matched in both codes), pooled over the pairs.
All cars: flips (yaw error > 90 degrees, the truth an oracle used only to score), the flip share branch - main.
Cut cars (the ground truth's 312x96 box cut by the left or right border, lamps.border_side not 0, the cars
FitSettings.cut_inward can touch): median yaw error of each code, yaw error branch - main per car, flips. Intervals:
10,000-resample paired bootstrap 95 % (seed 0); better / worse counts. ROW: gt_fit, gt_branch or pred_fit.
Run: PYTHONPATH=/work/wt/inward/src python cutpaired.py gt_fit main31.json:branch31.json ..."""
import json
import sys

import numpy as np
import torch

from sdn3d.geometric.lamps import border_side

ROWS = {"gt_branch": "branch, oracle: ground-truth masks", "gt_fit": "fit, oracle: ground-truth masks + boxes",
        "pred_fit": "fit, predicted proposals"}


def ci(d: np.ndarray) -> str:
    rng = np.random.default_rng(0)
    means = d[rng.integers(0, len(d), (10_000, len(d)))].mean(1)
    lo, hi = np.percentile(means, [2.5, 97.5])
    return f"{d.mean():+.4f} [{lo:+.4f}, {hi:+.4f}] better {int((d < 0).sum())} / worse {int((d > 0).sum())}"


def main() -> None:
    row = sys.argv[1]
    a, b, cut = [], [], []
    for pair in sys.argv[2:]:
        ca, cb = ({(o["frame"], o["id"]): o for o in json.load(open(p))["objects"][ROWS[row]]}
                  for p in pair.split(":"))
        for k, o in ca.items():
            if k not in cb or (row == "pred_fit" and not (o["matched"] and cb[k]["matched"])):
                continue
            a.append(o["yaw_deg"])
            b.append(cb[k]["yaw_deg"])
            cut.append(float(border_side(torch.tensor([o["box"]]), 312)[0]) != 0)
    a, b, cut = np.array(a), np.array(b), np.array(cut)
    print(f"{ROWS[row]} ({row}): {len(a)} cars; flips main {int((a > 90).sum())} ({(a > 90).mean():.1%}), "
          f"branch {int((b > 90).sum())} ({(b > 90).mean():.1%})")
    print(f"  flip share, branch - main: {ci((b > 90).astype(float) - (a > 90).astype(float))}")
    print(f"  yaw error (deg), branch - main, all cars: {ci(b - a)}; median {np.median(a):.2f} -> {np.median(b):.2f}")
    ac, bc = a[cut], b[cut]
    print(f"  cut cars (left or right border): {len(ac)}; median yaw error main {np.median(ac):.2f}, branch "
          f"{np.median(bc):.2f}; mean {ac.mean():.2f} -> {bc.mean():.2f}; flips {int((ac > 90).sum())} -> "
          f"{int((bc > 90).sum())}")
    print(f"  cut cars' yaw error (deg), branch - main: {ci(bc - ac)}")
    print(f"  cut cars' flip share, branch - main: {ci((bc > 90).astype(float) - (ac > 90).astype(float))}")
    print(f"  cars not cut that changed: {int((np.abs(b - a)[~cut] > 1e-6).sum())}")


if __name__ == "__main__":
    main()
