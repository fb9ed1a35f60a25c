"""replay_inward.py PREFIX... [--row gt_fit] [--limits ...]: a screen of dropping a cut car's inward hypotheses on
recorded fit decisions (border's diag.sh records of main's code, a9c9d5f's fit): each recorded object's
fine-stage hypotheses whose near end points away from the border that cuts its 312x96 box
(``side * sin(2 alpha) < -limit``, ``alpha = ry - ray`` with the box's ray) get their loss times 1 + penalty,
infinite by default (unless every one would), and fit._choose is replayed on the recorded losses, beliefs and
yaws. Counts flips (> 90 degrees from the truth, an oracle used only to score) and the cut cars' yaw errors, and
lists every car that changes. A screen only: the real fit uses each hypothesis' own ray.
Run: PYTHONPATH=/work/wt/inward/src:. python replay_inward.py /tmp/s23data/border/diag/brB_w0_31 ..."""
import argparse
import math
import statistics

import torch
from score import load

from sdn3d.geometric.fit import FitSettings, _choose
from sdn3d.geometric.lamps import border_side


def err_deg(a: float, b: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--row", default="gt_fit")
    ap.add_argument("--limits", type=float, nargs="+", default=[0.0, 0.2, 0.4, 0.6])
    ap.add_argument("--guard", action="store_true", help="keep main's winner where the drop's is believed less")
    ap.add_argument("--penalty", type=float, default=math.inf, help="inward losses times 1 + this (inf: dropped)")
    a = ap.parse_args()
    settings = FitSettings()
    cars = [c for c in load(a.prefixes, a.row) if c["diag"] is not None and c["diag"].get("has")]
    for limit in a.limits:
        n = flips0 = flips1 = fixed = broken = 0
        cut0, cut1 = [], []
        lines = []
        for c in cars:
            d = c["diag"]
            loss, ry, belief = torch.tensor([d["loss"]]), torch.tensor([d["hyp_ry"]]), torch.tensor([d["belief"]])
            side = float(border_side(torch.tensor([c["box"]], dtype=torch.float32), 312)[0])
            w0 = int(_choose(loss, belief, ry, settings)[0])
            w1 = w0
            if side != 0:
                inward = side * torch.sin(2 * (ry - d["app"]["ray"])) < -limit
                if not inward.all():
                    w1 = int(_choose(torch.where(inward, loss * (1 + a.penalty), loss), belief, ry, settings)[0])
                    if a.guard and float(belief[0, w1]) < float(belief[0, w0]):
                        w1 = w0
                e0, e1 = err_deg(d["hyp_ry"][w0], c["true_ry"]), err_deg(d["hyp_ry"][w1], c["true_ry"])
                cut0.append(e0)
                cut1.append(e1)
            else:
                e0 = e1 = err_deg(d["hyp_ry"][w0], c["true_ry"])
            n += 1
            flips0 += e0 > 90
            flips1 += e1 > 90
            fixed += e0 > 90 >= e1
            broken += e1 > 90 >= e0
            if w0 != w1:
                tree = c["tree"].rsplit("_", 1)[-1]
                lines.append(f"  {tree} {c['frame']:26} {c['id']} side {int(side):+d} err {e0:5.1f} -> {e1:5.1f}")
        better = sum(x < y - 1 for x, y in zip(cut1, cut0, strict=True))
        worse = sum(x > y + 1 for x, y in zip(cut1, cut0, strict=True))
        print(f"{a.row} limit {limit} penalty {a.penalty}: {n} cars, flips {flips0} -> {flips1} "
              f"(fixed {fixed}, broken {broken}); "
              f"{len(cut0)} side-cut cars: median yaw error {statistics.median(cut0):.1f} -> "
              f"{statistics.median(cut1):.1f}, mean {statistics.mean(cut0):.1f} -> {statistics.mean(cut1):.1f}, "
              f"better/worse by > 1 deg {better}/{worse}")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
