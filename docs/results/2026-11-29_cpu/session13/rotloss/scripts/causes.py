# ruff: noqa: E501, E701, E702
"""causes.py POSES.json...: each entry 3D-SDN loses to the 2D paste (PSNR all) put in one cause class by its worst
modify operation's fitted pose against the truth (oracle, scoring only; poses.py) and by where its loss lies
(ana.py's linearised per-pixel classes); first rule that holds wins:
  pick misses: the proposal picked for an operation overlaps its car at mask IoU < 0.3 (another or a cut proposal);
  flip: a modified car's fitted yaw is > 90 deg off (end for end);
  wrong yaw: 20-90 deg off;
  size/template: the fitted length over the true one, divided by the distance ratio (a uniform scale of car and
    distance projects the same), is outside [0.87, 1.15];
  distance: |distance ratio - 1| > 0.15 (not explained by a matching size);
  removal fill: the loss lies mostly on vacated pixels the target does not show the car on (~T&fill);
  drawn past the car: mostly 3D-SDN's car drawn where the target has no edited car (~T&drawn);
  unseen side: a turn of 90 deg or more, the loss mostly on the drawn car over the target car (T&drawn);
  drawn car (other): the loss mostly T&drawn, turn under 90;
  other.
Prints per file and pooled: count and summed loss (dB) of each class and its share of the total loss."""
import json
import sys
from collections import defaultdict


def cause(r):
    mods = [o for o in r["ops"] if o["type"] == "modify"]
    ops = [o for o in r["ops"] if "mask_iou" in o]
    if any(o["mask_iou"] < 0.3 for o in ops): return "pick misses the car"
    posed = [o for o in mods if "yaw_err" in o]
    if any(abs(o["yaw_err"]) > 90 for o in posed): return "end-for-end flip"
    if any(abs(o["yaw_err"]) > 20 for o in posed): return "wrong yaw (20-90 deg)"
    if any(not 0.87 <= o["len_ratio"] / o["dist_ratio"] <= 1.15 for o in posed): return "size/template (length)"
    if any(abs(o["dist_ratio"] - 1) > 0.15 for o in posed): return "distance"
    cls = {k: r.get(k, 0.0) for k in ("T&drawn", "~T&drawn", "T&fill", "~T&fill", "T&input")}
    worst = min(cls, key=cls.get)
    if worst == "~T&fill": return "removal fill (vacated area)"
    if worst == "~T&drawn": return "drawn past the car (pose ok)"
    if worst == "T&drawn":
        return "unseen side drawn (turn >= 90)" if any(abs(o["turn_deg"]) >= 90 for o in mods) else "drawn car, other (turn < 90)"
    return f"other ({worst})"


def main(files):
    pooled = defaultdict(lambda: [0, 0.0]); ptot = 0.0
    for f in files:
        rows = [r for r in json.load(open(f)) if r["d_all"] < 0]
        tot = sum(r["d_all"] for r in rows); ptot += tot
        by = defaultdict(lambda: [0, 0.0, []])
        for r in rows:
            c = cause(r); by[c][0] += 1; by[c][1] += r["d_all"]; by[c][2].append(r["index"])
            pooled[c][0] += 1; pooled[c][1] += r["d_all"]
        print(f"== {f}: {len(rows)} losing entries, summed loss {tot:+.2f} dB")
        for c, (k, s, ix) in sorted(by.items(), key=lambda kv: kv[1][1]):
            print(f"  {c:34s} n {k:3d}  {s:+7.2f} dB  share {s / tot:5.1%}  entries {sorted(ix)}")
    print(f"== pooled: summed loss {ptot:+.2f} dB")
    for c, (k, s) in sorted(pooled.items(), key=lambda kv: kv[1][1]):
        print(f"  {c:34s} n {k:3d}  {s:+7.2f} dB  share {s / ptot:5.1%}")


if __name__ == "__main__":
    main(sys.argv[1:])
