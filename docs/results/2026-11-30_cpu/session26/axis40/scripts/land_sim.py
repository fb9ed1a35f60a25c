"""land_sim.py PREFIX...: replays choice rules on landscape.py's refits of every car of row gt_fit (ground-truth masks
+ boxes, an oracle; the truth, an oracle, only scores): for a set of starting offsets from the winner's yaw (degrees,
at the winner's end), the refit with the lowest loss replaces the winner (``keep``: only where its loss is below the
winner's own). Per rule: mean axis error (the yaw error modulo 180) and yaw error change against the winner, 95 %
bootstrap interval, better/worse cars, flips. Usage:

    python land_sim.py /tmp/s26data/axis40/land_35 /tmp/s26data/axis40/land_37
"""
import json
import math
import sys

import numpy as np

ROW = "fit, oracle: ground-truth masks + boxes"
RULES = {"0": [0], "0,+-10": [0, -10, 10], "0,+-20": [0, -20, 20], "0,+-30": [0, -30, 30],
         "0,+-20,+-40": [0, -20, 20, -40, 40], "all 9": list(range(-40, 41, 10)), "+-20 only": [-20, 20]}


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
        cars += [(o, land[(o["frame"], o["ry"])]) for o in table
                 if (o["frame"], o["ry"]) in land and land[(o["frame"], o["ry"])]["fitted"]]
    print(f"{len(cars)} cars (ground-truth masks + boxes, oracle)")
    for name, offs in RULES.items():
        for keep in (False, True):
            ax, yaw, flips = [], [], 0
            for o, d in cars:
                idx = [round(math.degrees(wrap(s - o["ry"]))) for s in d["start"]]
                rows = [i for i, v in enumerate(idx) if v in offs]
                i = min(rows, key=lambda j: d["loss"][j])
                ry = d["end"][i] if (not keep or d["loss"][i] < d["win_loss"]) else o["ry"]
                ax.append(axis_err(ry, o["true_ry"]) - axis_err(o["ry"], o["true_ry"]))
                yaw.append(abs(math.degrees(wrap(ry - o["true_ry"]))) - o["yaw_deg"])
                flips += abs(math.degrees(wrap(ry - o["true_ry"]))) > 90
            print(f"{name:14} keep={keep!s:5}: axis error {ci(np.array(ax))}; yaw error {ci(np.array(yaw))}; "
                  f"flips {flips} (main {sum(o['yaw_deg'] > 90 for o, _ in cars)})")


if __name__ == "__main__":
    main()
