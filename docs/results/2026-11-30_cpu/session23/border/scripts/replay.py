"""replay.py PREFIX... [--row gt_fit]: a screen of the border rule on recorded fit decisions (diag.sh's records of
main's code): each recorded object's belief recomputed with facing_belief of the code on the path, once without
and once with ``border_side`` (lamps.border_side of the car's 312x96 box), and fit._choose replayed on the
recorded losses and yaws. Counts flips (> 90 degrees from the truth, an oracle used only to score) either way,
and lists every car that changes. It does not move the branch's own yaw (the fit's first start), which the real
run does. Run: PYTHONPATH=BRANCH/src:. python replay.py /tmp/s22data/flip/diag/hw03_w0_31 ..."""
import argparse
import math

import torch
from score import load, reading, tensors

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.fit import FitSettings, _choose
from sdn3d.geometric.lamps import LampCue, border_side


def err_deg(a: float, b: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--row", default="gt_fit")
    ap.add_argument("--traffic", default="right")
    a = ap.parse_args()
    settings = FitSettings()
    n = flips0 = flips1 = fixed = broken = 0
    for c in load(a.prefixes, a.row):
        d = c["diag"]
        if d is None or "app" not in d or not d["has"]:
            continue
        cue = LampCue(**{**d["cue"], "traffic": a.traffic})
        app = tensors(d["app"])
        loss, ry = torch.tensor([d["loss"]]), torch.tensor([d["hyp_ry"]])
        w0 = int(_choose(loss, facing_belief(app, cue)(ry), ry, settings)[0])
        app["border_side"] = border_side(torch.tensor([c["box"]]), 312)
        w1 = int(_choose(loss, facing_belief(app, cue)(ry), ry, settings)[0])
        e0, e1 = err_deg(d["hyp_ry"][w0], c["true_ry"]), err_deg(d["hyp_ry"][w1], c["true_ry"])
        n += 1
        flips0 += e0 > 90
        flips1 += e1 > 90
        fixed += e0 > 90 >= e1
        broken += e1 > 90 >= e0
        if w0 != w1:
            tree = c["tree"].rsplit("_", 1)[-1]
            print(f"  {tree} {c['frame']:26} {c['id']} side {int(app['border_side'])} {reading(d['app'], cue):26} "
                  f"err {e0:5.1f} -> {e1:5.1f}")
    print(f"{a.row}: {n} cars, flips {flips0} -> {flips1} (fixed {fixed}, broken {broken})")


if __name__ == "__main__":
    main()
