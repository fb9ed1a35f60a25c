"""replay_tie.py ROW PREFIX... : the fit's choice (fit._choose on each object's recorded fine-stage losses, beliefs and
yaws, diag_pose.py) replayed with other ``facing_tie`` values, flips (> 90 degrees from the truth, an oracle used only
to score) per value, and the cars each value fixes / breaks against the recorded winner. ROW: gt_fit (ground-truth
masks + boxes, an oracle) or pred_fit (predicted proposals, matched cars). The border rule's second choice
(cut_inward) is not replayed: cars the border cuts are counted apart. Run with a code's library on the path."""
import json
import math
import sys
from collections import defaultdict

import torch

from sdn3d.geometric.fit import FitSettings, _choose

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}
TIES = (0.5, 0.75, 1.0, 1.5, 2.0)


def err(a: float, b: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))


def main() -> None:
    row, prefixes = sys.argv[1], sys.argv[2:]
    flips = defaultdict(int)
    moved = defaultdict(lambda: [0, 0])
    n = 0
    for p in prefixes:
        table = json.load(open(p + ".json"))
        diag = defaultdict(list)
        for d in json.load(open(p + ".diag.json")):
            if d["row"] == row:
                diag[(d["frame"], d["ry"])].append(d)
        for o in table["objects"][ROWS[row]]:
            if not o["matched"]:
                continue
            hit = diag.get((o["frame"], o["ry"]), [])
            if len(hit) != 1 or "app" not in hit[0]:
                continue
            d = hit[0]
            if d["app"].get("border_side", 0.0) != 0:
                continue
            n += 1
            loss, belief, ry = (torch.tensor([d[k]]) for k in ("loss", "belief", "hyp_ry"))
            base = err(d["hyp_ry"][d["winner"]], o["true_ry"]) > 90
            for tie in TIES:
                w = int(_choose(loss, belief, ry, FitSettings(facing_tie=tie))[0])
                f = err(d["hyp_ry"][w], o["true_ry"]) > 90
                flips[tie] += f
                moved[tie][0] += base and not f
                moved[tie][1] += f and not base
    print(f"{row}: {n} cars not cut by a side border (recorded winners: {flips[0.5]} flips at the default 0.5)")
    for tie in TIES:
        print(f"  facing_tie {tie}: flips {flips[tie]} ({100 * flips[tie] / max(n, 1):.1f} %), fixed "
              f"{moved[tie][0]}, broken {moved[tie][1]}")


if __name__ == "__main__":
    main()
