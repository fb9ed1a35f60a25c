"""axis_paired.py ROW MAIN.json:BRANCH.json [...]: the axis error (the yaw error modulo 180 degrees, apart from the
end; the truth is an oracle, only scoring) of two codes' pose tables paired per car (frame and instance id), pooled
over the pairs: per code the mean and the right-end cars more than 15 degrees off the axis; branch - main per car,
mean, 10,000-resample paired bootstrap 95 % interval (seed 0), cars better / worse (by more than 0.5 degrees).
ROW: gt_fit (ground-truth masks + boxes, an oracle) or pred_fit (predicted proposals, the cars matched in both)."""
import json
import math
import sys

import numpy as np

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}


def axis_err(o: dict) -> float:
    e = abs(math.degrees(math.atan2(math.sin(o["ry"] - o["true_ry"]), math.cos(o["ry"] - o["true_ry"]))))
    return min(e, 180 - e)


def main() -> None:
    row, a, b, ra, rb = sys.argv[1], [], [], [], []
    for pair in sys.argv[2:]:
        fa, fb = pair.split(":")
        ca = {(o["frame"], o["id"]): o for o in json.load(open(fa))["objects"][ROWS[row]]}
        cb = {(o["frame"], o["id"]): o for o in json.load(open(fb))["objects"][ROWS[row]]}
        for k in ca:
            if k in cb and (row != "pred_fit" or (ca[k]["matched"] and cb[k]["matched"])):
                a.append(axis_err(ca[k]))
                b.append(axis_err(cb[k]))
                ra.append(ca[k]["yaw_deg"] <= 90)
                rb.append(cb[k]["yaw_deg"] <= 90)
    a, b, ra, rb = map(np.array, (a, b, ra, rb))
    d = b - a
    rng = np.random.default_rng(0)
    lo, hi = np.percentile(d[rng.integers(0, len(d), (10_000, len(d)))].mean(1), [2.5, 97.5])
    print(f"== {row}: {len(d)} cars; axis error mean main {a.mean():.2f}, branch {b.mean():.2f}; right end and axis "
          f"> 15 deg: main {int((ra & (a > 15)).sum())}, branch {int((rb & (b > 15)).sum())}")
    print(f"  branch - main, axis error (deg): {d.mean():+.2f} [{lo:+.2f}, {hi:+.2f}] better {int((d < -0.5).sum())} / "
          f"worse {int((d > 0.5).sum())}")


if __name__ == "__main__":
    main()
