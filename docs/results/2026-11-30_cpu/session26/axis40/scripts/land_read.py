"""land_read.py PREFIX...: landscape.py's fits (PREFIX.land.json) joined to the pose table (PREFIX.json, row gt_fit:
ground-truth masks + boxes, an oracle) by frame and final yaw. For each car whose end is right but whose axis is more
than 15 degrees off (the truth, an oracle, read only to score), the best loss the fit's own fine stage reaches from
the winner's template, size, place and FFD when started within 10 degrees of the true axis at the winner's end
(``right``) and at the other end (``rev``), against the winner's loss; and where those starts ended. Usage:

    python land_read.py /tmp/s26data/axis40/land_35 /tmp/s26data/axis40/land_37
"""
import json
import math
import sys
from collections import Counter

ROW = "fit, oracle: ground-truth masks + boxes"


def wrap(d: float) -> float:
    return math.atan2(math.sin(d), math.cos(d))


def axis_err(ry: float, true: float) -> float:
    e = abs(math.degrees(wrap(ry - true)))
    return min(e, 180 - e)


def best(d: dict, ix: list[int], true: float) -> tuple[float, float, float]:
    """(loss, axis error, end yaw in degrees) of the lowest-loss refit among the starts ``ix``."""
    if not ix:
        return math.inf, math.nan, math.nan
    i = min(ix, key=lambda j: d["loss"][j])
    return d["loss"][i], axis_err(d["end"][i], true), math.degrees(d["end"][i])


def main() -> None:
    counts: Counter = Counter()
    for p in sys.argv[1:]:
        table = json.load(open(p + ".json"))["objects"][ROW]
        land = {(d["frame"], d["ry"]): d for d in json.load(open(p + ".land.json"))}
        for o in table:
            d = land.get((o["frame"], o["ry"]))
            true = o["true_ry"]
            if d is None or o["yaw_deg"] > 90 or axis_err(o["ry"], true) <= 15:
                continue
            near = [i for i, s in enumerate(d["start"]) if axis_err(s, true) <= 10]
            right = [i for i in near if abs(wrap(d["start"][i] - true)) <= math.pi / 2]
            rev = [i for i in near if i not in right]

            rl, ra, rend = best(d, right, true)
            vl, va, vend = best(d, rev, true)
            w = d["win_loss"]
            own = min(range(len(d["loss"])), key=lambda j: d["loss"][j])
            kind = ("on-axis start at the right end beats the winner" if rl < w else
                    "on-axis start at the reversed end beats the winner" if vl < w else "the winner's loss is lowest")
            counts[kind] += 1
            print(f"{p.rsplit('_', 1)[-1]} {o['frame']} {o['id']} px {o['pixels']}: true {math.degrees(true):+.0f} fit "
                  f"{math.degrees(o['ry']):+.0f} loss {w:.4f} | right-end axis start -> {rend:+.0f} (axis {ra:.0f}) "
                  f"{rl:.4f} | reversed -> {vend:+.0f} (axis {va:.0f}) {vl:.4f} | landscape best "
                  f"{math.degrees(d['end'][own]):+.0f} {d['loss'][own]:.4f}; {kind}")
    for k, v in counts.items():
        print(f"-> {k}: {v}")


if __name__ == "__main__":
    main()
