# ruff: noqa: E402, E501, E701, E702
"""replay.py TREE CAPTURE_DIR OUT.json VARIANT[,VARIANT...]: the captured proposal fits (capture.py) fitted again with
this tree's code, once per variant in the list (a number: FitSettings.template_belief_reg; else NAME=VALUE[+NAME=VALUE]
FitSettings fields, e.g. template_trust=2; "base": the defaults), each fitted vehicle matched to the
ground-truth car of largest mask IoU (>= 0.3; the truth is an oracle, used only to score): per car the branch's template
belief (its softmax) and argmax, the truth's template, and per setting the fitted template, yaw error, length and
distance ratios and the winning hypothesis. summary.py reads the JSON."""
import glob
import json
import math
import os
import sys

import torch

import sdn3d.proposal_fit as pf
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings

tree, cap, out, variants = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split(",")


def settings_of(variant):
    try:
        return FitSettings(template_belief_reg=float(variant))
    except ValueError:
        pass
    fields = dict(kv.split("=") for kv in variant.split("+") if kv != "base")
    return FitSettings(**{k: type(getattr(FitSettings(), k))(v) for k, v in fields.items()})


regs = {v: settings_of(v) for v in variants}
records = index_records(read_frames(tree))
torch.set_num_threads(1)


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


cars = []
for f in sorted(glob.glob(f"{cap}/*.pt")):
    c = torch.load(f, weights_only=False)
    _, w, var, fr = c["source"].split("/")
    truth = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects
    fitted = {}
    for reg, settings in regs.items():
        fitted[reg] = pf.fit_proposals(c["intr"], c["masks"], c["ids"], c["rows"], c["geometry"], settings,
                                       c["appearance"], c["unsure"], c["classes"], c["template_belief"])
    for k, r in enumerate(c["rows"].tolist()):
        P = c["masks"][r]
        inter = (P[None] & truth.mask).flatten(1).sum(1).float(); uni = (P[None] | truth.mask).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1); t = int(iou.argmax())
        if float(iou[t]) < 0.3 or int(truth.template_id[t]) < 0: continue
        car = {"src": c["source"], "id": int(c["ids"][r]), "px": int(P.sum()), "iou": float(iou[t]),
               "class": c["classes"][r], "truth_tpl": int(truth.template_id[t]),
               "branch_tpl": int(c["geometry"][0][r]), "belief": [round(float(p), 5) for p in c["template_belief"][r]],
               "branch_yaw_err": math.degrees(wrap(float(c["geometry"][2][r]) - float(truth.ry[t]))), "fits": {}}
        for reg, (geometry, recs) in fitted.items():
            template, dims, ry, location, _ = geometry
            car["fits"][reg] = {
                "tpl": int(template[r]), "yaw_err": math.degrees(wrap(float(ry[r]) - float(truth.ry[t]))),
                "len_ratio": float(dims[r, 0] / truth.dims[t, 0]),
                "dist_ratio": float(location[r].norm() / truth.location[t].norm()),
                "hyp": recs[k].hypothesis, "fit_iou": recs[k].iou}
        cars.append(car)
    print(c["source"], len(c["rows"]), flush=True)
with open(out + ".tmp", "w") as fh:
    json.dump(cars, fh)
os.replace(out + ".tmp", out)
