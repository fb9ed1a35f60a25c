"""axis.py PREFIX...: the fitted yaw's axis error (the error modulo 180 degrees, apart from the end) of every car on
the two fit rows of diag.sh's pose tables (gt_fit: ground-truth masks + boxes, an oracle; pred_fit: predicted
proposals, matched cars), and for the cars whose end is right but whose axis is off by more than ``LIMIT`` (15)
degrees, what the fit's own hypotheses held (diag_pose.py's spy): whether a hypothesis on the reversed end reached
the true axis (within ``LIMIT``) with a lower loss than the winner, and whether a right-end one did. The truth is an
oracle, read only to score. PREFIX: diag.sh's output prefix (PREFIX.json, PREFIX.diag.json). No library needed:

    python axis.py /tmp/s26data/axis40/main_31 /tmp/s26data/axis40/main_33 ... > axis_main.txt
"""
import json
import math
import sys
from collections import defaultdict

import numpy as np

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}
LIMIT = 15.0


def wrap(d: float) -> float:
    return math.atan2(math.sin(d), math.cos(d))


def axis_err(ry: float, true: float) -> float:
    """Degrees in [0, 90]: the yaw's error modulo 180."""
    e = abs(math.degrees(wrap(ry - true)))
    return min(e, 180 - e)


def cars_of(prefix: str) -> dict[str, list[dict]]:
    table = json.load(open(prefix + ".json"))
    diag = json.load(open(prefix + ".diag.json"))
    by = defaultdict(list)
    for d in diag:
        by[(d["row"], d["frame"], d["ry"])].append(d)
    out = {}
    for row, name in ROWS.items():
        cars = []
        for o in table["objects"].get(name, []):
            if row == "pred_fit" and not o["matched"]:
                continue
            hs = by.get((row, o["frame"], o["ry"]), [])
            hs = [d for d in hs if d.get("gt_id") in (None, o["id"])] or hs
            cars.append({"tree": prefix.rsplit("_", 1)[-1], "o": o, "d": hs[0] if len(hs) == 1 else None})
        out[row] = cars
    return out


def main() -> None:
    rows = defaultdict(list)
    for p in sys.argv[1:]:
        for row, cars in cars_of(p).items():
            rows[row] += cars
    for row, cars in rows.items():
        ax = np.array([axis_err(c["o"]["ry"], c["o"]["true_ry"]) for c in cars])
        right = np.array([c["o"]["yaw_deg"] <= 90 for c in cars])
        off = [c for c, a, r in zip(cars, ax, right, strict=True) if r and a > LIMIT]
        print(f"== {ROWS[row]}: {len(cars)} cars; axis error median {np.median(ax):.2f}, mean {ax.mean():.2f}, "
              f"p90 {np.percentile(ax, 90):.2f}; flips {int((~right).sum())}; right end, axis > {LIMIT:.0f} deg: "
              f"{len(off)}")
        counts = defaultdict(int)
        for c in off:
            o, d = c["o"], c["d"]
            true = o["true_ry"]
            if d is None:
                counts["no diag"] += 1
                print(f"  {c['tree']} {o['frame']} {o['id']}: axis {axis_err(o['ry'], true):.1f}, no diag")
                continue
            w = min(range(len(d["hyp_ry"])), key=lambda i: abs(wrap(d["hyp_ry"][i] - o["ry"])))
            wl = d["loss"][w]
            hyps = list(zip(d["hyp_ry"], d["loss"], strict=True))
            rev_on = [(r, lo) for r, lo in hyps if abs(wrap(r - true)) > math.pi / 2 and axis_err(r, true) <= LIMIT]
            right_on = [(r, lo) for r, lo in hyps if abs(wrap(r - true)) <= math.pi / 2 and axis_err(r, true) <= LIMIT]
            best = min(range(len(hyps)), key=lambda i: hyps[i][1])
            kind = ("reversed end on the axis, lower loss" if any(lo < wl for _, lo in rev_on) else
                    "reversed end on the axis, higher loss" if rev_on else
                    "right end on the axis, higher loss" if right_on else "no hypothesis on the axis")
            counts[kind] += 1
            hs = " ".join(f"{math.degrees(r):+.0f}/{lo:.3f}" for r, lo in hyps)
            print(f"  {c['tree']} {o['frame']} {o['id']} px {o['pixels']}: true {math.degrees(true):+.1f}, fit "
                  f"{math.degrees(o['ry']):+.1f} (axis {axis_err(o['ry'], true):.1f}, loss {wl:.3f}, hyp {w}); best "
                  f"loss hyp {best} {math.degrees(hyps[best][0]):+.0f}; {kind}; hyps {hs}")
        for k, v in sorted(counts.items()):
            print(f"  -> {k}: {v}")


if __name__ == "__main__":
    main()
