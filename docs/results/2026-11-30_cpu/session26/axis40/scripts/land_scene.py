"""land_scene.py PREFIX...: replays a scene-axis rule on landscape.py's refits (PREFIX.land.json, PREFIX.json; row
gt_fit, ground-truth masks + boxes, an oracle; the truth only scores): the frame's axis is the circular mean of the
doubled fitted yaws of the frame's other fitted cars (at least MIN_OTHERS); the refit started nearest that axis at the
winner's end (landscape.py's 10-degree grid, within 40 degrees of the winner) replaces the winner where its loss is
within TIE (a share) of the bar: the winner's own loss (``won``) or its refit from its own yaw (``refit``). Usage:

    python land_scene.py /tmp/s26data/axis40/land_35 /tmp/s26data/axis40/land_37
"""
import json
import math
import sys
from collections import defaultdict

import numpy as np

ROW = "fit, oracle: ground-truth masks + boxes"


def wrap(d: float) -> float:
    return math.atan2(math.sin(d), math.cos(d))


def axis_err(ry: float, true: float) -> float:
    e = abs(math.degrees(wrap(ry - true)))
    return min(e, 180 - e)


def ci(d: np.ndarray) -> str:
    rng = np.random.default_rng(0)
    m = d[rng.integers(0, len(d), (10_000, len(d)))].mean(1)
    lo, hi = np.percentile(m, [2.5, 97.5])
    return f"{d.mean():+.2f} [{lo:+.2f}, {hi:+.2f}] {int((d < -0.5).sum())}/{int((d > 0.5).sum())}"


def main() -> None:
    cars = []
    for p in sys.argv[1:]:
        table = json.load(open(p + ".json"))["objects"][ROW]
        land = {(d["frame"], d["ry"]): d for d in json.load(open(p + ".land.json"))}
        cars += [(p, o, land[(o["frame"], o["ry"])]) for o in table
                 if (o["frame"], o["ry"]) in land and land[(o["frame"], o["ry"])]["fitted"]]
    frames = defaultdict(list)
    for i, (p, o, _) in enumerate(cars):
        frames[(p, o["frame"])].append(i)
    for min_others in (1, 2, 3):
        for tie in (0.0, 0.05, 0.1, 0.2):
            for against in ("won", "refit"):
                ax, yaw, moved = [], [], 0
                for i, (p, o, d) in enumerate(cars):
                    others = [cars[j][1]["ry"] for j in frames[(p, o["frame"])] if j != i]
                    ry = o["ry"]
                    if len(others) >= min_others:
                        axis = 0.5 * math.atan2(sum(math.sin(2 * r) for r in others),
                                                sum(math.cos(2 * r) for r in others))
                        target = math.degrees(wrap(axis - ry))
                        target = math.degrees(wrap(math.radians(target + 180))) if abs(target) > 90 else target
                        offs = [math.degrees(wrap(s - ry)) for s in d["start"]]
                        if abs(target) > 5 and abs(target) <= 45:
                            k = min(range(len(offs)), key=lambda j: abs(offs[j] - target))
                            zero = min(range(len(offs)), key=lambda j: abs(offs[j]))
                            bar = d["win_loss"] if against == "won" else d["loss"][zero]
                            if d["loss"][k] <= bar * (1 + tie):
                                ry, moved = d["end"][k], moved + 1
                    ax.append(axis_err(ry, o["true_ry"]) - axis_err(o["ry"], o["true_ry"]))
                    yaw.append(abs(math.degrees(wrap(ry - o["true_ry"]))) - o["yaw_deg"])
                print(f"others>={min_others} tie {tie:.2f} against {against:5}: moves {moved:3}; axis error "
                      f"{ci(np.array(ax))}; yaw error {ci(np.array(yaw))}")


if __name__ == "__main__":
    main()
