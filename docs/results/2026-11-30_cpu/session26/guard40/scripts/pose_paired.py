"""pose_paired.py ROW MAIN.json:BRANCH.json [...]: two codes' pose tables (benchmarks/pose_table.py --out) on the same
trees, paired per car (frame and instance id), pooled over the pairs and per pair. ROW: gt_fit (fit on ground-truth
masks + boxes, an oracle), gt_branch or pred_fit (fit on predicted proposals: the cars matched in both codes; an
unmatched car has no pose to compare). Per code: cars, flips (yaw error > 90 degrees) and share, median and 90th
percentile yaw error; branch - main per car: the flip indicator and the yaw error (degrees), mean, 10,000-resample
paired bootstrap 95 % interval (seed 0), and cars better / worse (fewer flips / smaller error = better)."""
import json
import sys

import numpy as np

ROWS = {"gt_branch": "branch, oracle: ground-truth masks", "gt_fit": "fit, oracle: ground-truth masks + boxes",
        "pred_fit": "fit, predicted proposals"}


def ci(d: np.ndarray) -> str:
    rng = np.random.default_rng(0)
    means = d[rng.integers(0, len(d), (10_000, len(d)))].mean(1)
    lo, hi = np.percentile(means, [2.5, 97.5])
    return f"{d.mean():+.4f} [{lo:+.4f}, {hi:+.4f}] better {int((d < 0).sum())} / worse {int((d > 0).sum())}"


def pairs_of(row: str, fa: str, fb: str) -> tuple[np.ndarray, np.ndarray]:
    def cars(f: str) -> dict:
        return {(o["frame"], o["id"]): o for o in json.load(open(f))["objects"][ROWS[row]]}
    ca, cb = cars(fa), cars(fb)
    keys = [k for k in ca if k in cb and (row != "pred_fit" or (ca[k]["matched"] and cb[k]["matched"]))]
    return np.array([ca[k]["yaw_deg"] for k in keys]), np.array([cb[k]["yaw_deg"] for k in keys])


def report(label: str, a: np.ndarray, b: np.ndarray) -> None:
    print(f"== {label}: {len(a)} cars paired")
    for name, e in (("main", a), ("branch", b)):
        print(f"  {name:6}: flips {int((e > 90).sum())} ({100 * (e > 90).mean():.1f} %), median {np.median(e):.2f}, "
              f"p90 {np.percentile(e, 90):.2f}")
    if len(a):
        print(f"  branch - main, flip share: {ci((b > 90).astype(float) - (a > 90).astype(float))}")
        print(f"  branch - main, yaw error (deg): {ci(b - a)}")


row, pairs = sys.argv[1], [p.split(":") for p in sys.argv[2:]]
parts = [pairs_of(row, fa, fb) for fa, fb in pairs]
if len(parts) > 1:
    for (fa, _), (a, b) in zip(pairs, parts, strict=True):
        report(f"{row}, {fa.rsplit('/', 1)[-1]}", a, b)
report(f"{row}, pooled", np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]))
