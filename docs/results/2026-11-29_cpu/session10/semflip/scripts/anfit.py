# ruff: noqa: E402, E501, E701, E702
"""anfit.py SEM.pt GT.pt: per car (matched by frame and ground-truth id): yaw error of the fit on semantic proposals
and on ground-truth masks (oracle), the lamp reading (present/usable, lamp-mask px, red px), the net's yaw error,
the chosen hypothesis, and whether a hypothesis facing the true end existed and how it lost (loss ratio, belief)."""
import math
import sys

import torch

from sdn3d.geometric.lamps import LampCue, _red, through_the_air


def err(a, b): return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))
cue = LampCue()
def info(r):
    e = err(r["fit_ry"], r["true_ry"])
    o = {"err": e, "flip": e > 90, "iou": r["iou"], "hyp": r["fit"]["hypothesis"], "fit_iou": r["fit"]["fit_iou"]}
    if "seen" in r:
        m = r["lamps"][0] if r["lamps"].dim() == 3 else r["lamps"]
        seen = r["seen"].float()[None]
        red = _red(through_the_air(seen, m[None], cue.clear_dark), m[None], cue)
        o |= {"lp": bool(r["lamp_present"]), "lu": bool(r["lamp_usable"]), "fp": bool(r.get("front_present", False)), "fu": bool(r.get("front_usable", False)),
              "npx": int(m.sum()), "nred": int(red.sum()), "net_err": err(float(r["net_ry"]), r["true_ry"])}
    # best hypothesis facing the true end vs the chosen
    ry, loss, bel = r["hyp_ry"], r["loss"], r["belief"]
    right = torch.tensor([err(float(y), r["true_ry"]) < 60 for y in ry])
    c = r["index"]
    if right.any():
        k = int(torch.where(right, loss, torch.full_like(loss, 1e9)).argmin())
        o |= {"right_loss_ratio": float(loss[k] / loss[c]), "right_bel": float(bel[k]), "chosen_bel": float(bel[c])}
    else:
        o |= {"right_loss_ratio": None}
    return o
sem = torch.load(sys.argv[1], weights_only=False); gt = torch.load(sys.argv[2], weights_only=False)
G = {(r["key"], r["gt_id"]): r for r in gt}
n = {"sem": 0, "semflip": 0, "gtflip": 0}
for r in sem:
    a = info(r); g = G.get((r["key"], r["gt_id"])); b = info(g) if g else None
    n["sem"] += 1; n["semflip"] += a["flip"]; n["gtflip"] += bool(b and b["flip"])
    if a["flip"] or (b and b["flip"]):
        print(r["key"], r["gt_id"], "SEM", {k: (round(v, 2) if isinstance(v, float) else v) for k, v in a.items()})
        print("      GT ", {k: (round(v, 2) if isinstance(v, float) else v) for k, v in (b or {}).items()})
print(n)
