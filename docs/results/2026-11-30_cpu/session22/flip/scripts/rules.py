"""rules.py ROW PREFIX...: replays the fit's choice (fit._choose on the recorded fine losses and yaws of diag.sh's
runs, main's code on the path) with the belief of each candidate rule below, and counts the flips (> 90 degrees
from the truth; an oracle, used only to score) per rule against main's, per tree and pooled. Objects whose choice
was not recorded (no prediction, unmatched) keep their recorded error. ROW: gt_fit or pred_fit.

The rules (each a belief of one object's hypotheses, the recorded reading):
  main               facing.facing_belief as it is;
  white=W            a red body's headlights PRESENT count W times (their absence as before);
  cut                a car whose box touches the image border: its red lamps' absence is not read (the bins say);
  net=K              the bins' weight K instead of -flip_below."""
import math
import sys
from collections import Counter

import torch
from score import load, tensors

from sdn3d.geometric.fit import FitSettings, _choose
from sdn3d.geometric.lamps import LampCue
from sdn3d.geometric.model import yaw_distribution


def belief(app: dict, cue: LampCue, ry: torch.Tensor, cut: bool, rule: dict) -> torch.Tensor:
    v = tensors(app)
    alpha = ry - v["ray"][:, None]
    sin, cos = torch.sin(alpha), torch.cos(alpha)
    present, usable, offset = bool(app["lamp_present"]), bool(app["lamp_usable"]), float(app["lamp_offset"])
    if present:
        red = -(sin + 2 * offset * cos)
    else:
        red = cue.absent_weight * sin * (0.0 if rule.get("cut") and cut else 1.0)
    lamps = red if usable else torch.zeros_like(sin)
    if "front_usable" in app and app["front_usable"] and not usable:
        if app["front_present"]:
            lamps = rule.get("white", 1.0) * (sin + 2 * float(app["front_offset"]) * cos)
        else:
            lamps = -cue.absent_weight * sin
    raw = {k: v[k] for k in ("yaw_bins", "yaw_residual", "yaw_ray")}
    net = 2 * yaw_distribution(raw, ry) - 1
    return lamps + rule.get("net", -cue.flip_below) * net


def parse(name: str) -> dict:
    if name == "main":
        return {}
    out = {}
    for part in name.split("+"):
        k, _, val = part.partition("=")
        out[k] = float(val) if val else True
    return out


RULES = ["main", "white=0", "white=0.3", "white=0.5", "cut", "cut+white=0", "net=0.6", "net=1", "white=0+net=0.6"]
settings = FitSettings()
row, prefixes = sys.argv[1], sys.argv[2:]
cars = load(prefixes, row)
flips: dict[str, Counter] = {r: Counter() for r in RULES}
errs: dict[str, list[float]] = {r: [] for r in RULES}
for c in cars:
    d = c["diag"]
    tree = c["tree"].rsplit("_", 1)[-1]
    for name in RULES:
        err = c["yaw_deg"]
        if d is not None and "app" in d and d["has"]:
            ry = torch.tensor([d["hyp_ry"]])
            b = belief(d["app"], LampCue(**d["cue"]), ry, bool(c["truncated"]), parse(name)).float()
            i = int(_choose(torch.tensor([d["loss"]]), b, ry, settings)[0])
            if name == "main":
                assert i == d["winner"], (c["frame"], c["id"])
            delta = float(ry[0, i]) - c["true_ry"]
            # the recorded winner may be moved after the choice (a bad mask keeps its prediction): keep its error
            err = c["yaw_deg"] if i == d["winner"] else abs(math.degrees(math.atan2(math.sin(delta), math.cos(delta))))
        flips[name][tree] += err > 90
        flips[name]["all"] += err > 90
        errs[name].append(err)
n = len(cars)
print(f"== {row}: {n} cars over {', '.join(p.rsplit('/', 1)[-1] for p in prefixes)}")
for name in RULES:
    e = torch.tensor(errs[name])
    better = sum((a <= 90 < b) for a, b in zip(errs[name], errs["main"], strict=True))
    worse = sum((b <= 90 < a) for a, b in zip(errs[name], errs["main"], strict=True))
    per = " ".join(f"{k} {v}" for k, v in sorted(flips[name].items()) if k != "all")
    print(f"  {name:18} flips {flips[name]['all']:3d} ({100 * flips[name]['all'] / n:4.1f} %) [{per}] "
          f"fixed {better} broken {worse}; median {float(e.median()):.2f}")
