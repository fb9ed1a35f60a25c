"""cutcars.py PREFIX... [--row gt_fit]: the cars cut by the image border in diag.sh's pose tables, with what the
lamp cue read, which border cuts the box (312x96: left, right, bottom, top), and at the TRUE yaw (an oracle, used
only to score) the view (front / back / side) and the side of the image where the end facing the camera lies
(the near end: the same for a yaw and its reverse), so whether the border cuts the near end, and whether the
traffic's side (right-hand: cut by the right border a back, by the left a front) names the true end.
Run with score.py beside it: PYTHONPATH=TREE/src python cutcars.py /tmp/.../main_w0_31 ..."""
import argparse
import math
from collections import Counter

from score import load, reading

from sdn3d.geometric.lamps import LampCue

W, H = 312, 96


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--row", default="gt_fit")
    a = ap.parse_args()
    tally: Counter = Counter()
    for c in load(a.prefixes, a.row):
        d = c["diag"]
        if not c["truncated"] or d is None or "app" not in d or not d["has"]:
            continue
        app, cue = d["app"], LampCue(**d["cue"])
        x0, y0, x1, y1 = c["box"]
        sides = "".join(s for s, hit in (("L", x0 <= 0.5), ("R", x1 >= W - 0.5), ("B", y1 >= H - 0.5),
                                          ("T", y0 <= 0.5)) if hit)
        alpha = c["true_ry"] - app["ray"]
        s, co = math.sin(alpha), math.cos(alpha)
        view = "side" if abs(s) < 0.3 else ("back" if s < 0 else "front")
        near = math.copysign(1, s) * co  # the near end's direction across the image (+: right; lamps module doc)
        near_cut = (near < -0.3 and "L" in sides) or (near > 0.3 and "R" in sides)
        ok = "flip" if c["yaw_deg"] > 90 else "ok"
        kind = reading(app, cue)
        side = 0 if ("L" in sides) == ("R" in sides) else (1 if "L" in sides else -1)
        traffic = "abstain" if side == 0 or view == "side" else (
            "right" if (side > 0) == (view == "front") else "wrong")
        tally[(kind, view, f"near end cut {int(near_cut)}", f"traffic {traffic}", ok)] += 1
        tree = c["tree"].rsplit("_", 1)[-1]
        print(f"{tree} {c['frame']:26} {c['id']} px {c['pixels']:5d} {sides:3} {kind:26} {view:5} "
              f"near {near:+.2f} near_cut {int(near_cut)} traffic {traffic:7} err {c['yaw_deg']:5.1f} {ok}")
    for k, v in sorted(tally.items()):
        print(k, v)


if __name__ == "__main__":
    main()
