"""guard_replay.py MAIN.json:BRANCH.json...: a post-hoc replay (after held-out 2255; decides nothing) of one more
guard on the street-axis refit: keep a refit only where its yaw ends nearer the street's axis than the winner's did
(the refit's yaw is free, and a refit can run away from the axis and still fit within the tie). Row gt_fit
(ground-truth masks + boxes, an oracle; the truth only scores). The street's axis of a car is recomputed from main's
yaws of the frame's other evaluated cars (the branch's first choice is main's), with the fit's rules (at least 2
others, agreement 0.9); a car whose yaw the branch changed and whose branch yaw lies farther from that axis than
main's goes back to main's. Prints branch - main yaw error with and without the guard (bootstrap as pose_paired.py)."""
import json
import math
import sys
from collections import defaultdict

import numpy as np

ROW = "fit, oracle: ground-truth masks + boxes"


def off(ry: float, axis: float) -> float:
    d = abs(math.degrees(math.atan2(math.sin(ry - axis), math.cos(ry - axis))))
    return min(d, 180 - d)


def ci(d: np.ndarray) -> str:
    rng = np.random.default_rng(0)
    lo, hi = np.percentile(d[rng.integers(0, len(d), (10_000, len(d)))].mean(1), [2.5, 97.5])
    return f"{d.mean():+.3f} [{lo:+.3f}, {hi:+.3f}] better {int((d < 0).sum())} / worse {int((d > 0).sum())}"


def main() -> None:
    plain, guarded, reverted = [], [], 0
    for pair in sys.argv[1:]:
        fa, fb = pair.split(":")
        ca = {(o["frame"], o["id"]): o for o in json.load(open(fa))["objects"][ROW]}
        cb = {(o["frame"], o["id"]): o for o in json.load(open(fb))["objects"][ROW]}
        frames = defaultdict(list)
        for k in ca:
            frames[k[0]].append(k)
        for k, a in ca.items():
            b = cb[k]
            d = b["yaw_deg"] - a["yaw_deg"]
            plain.append(d)
            others = [ca[j]["ry"] for j in frames[k[0]] if j != k]
            if abs(a["ry"] - b["ry"]) > 1e-3 and len(others) >= 2:
                c, s = sum(math.cos(2 * r) for r in others), sum(math.sin(2 * r) for r in others)
                if math.hypot(c, s) >= 0.9 * len(others):
                    axis = 0.5 * math.atan2(s, c)
                    if off(b["ry"], axis) > off(a["ry"], axis):
                        reverted += 1
                        d = 0.0
            guarded.append(d)
    print(f"{len(plain)} cars (ground-truth masks + boxes, oracle); branch - main yaw error (deg)")
    print(f"  as measured:  {ci(np.array(plain))}")
    print(f"  with the guard ({reverted} refits reverted): {ci(np.array(guarded))}")


if __name__ == "__main__":
    main()
