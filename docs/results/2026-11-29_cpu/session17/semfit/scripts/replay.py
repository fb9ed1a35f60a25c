# ruff: noqa: E402, E501, E701, E702
"""replay.py TREE CAPTURE_DIR VARIANT OUT.json: the captured proposal fits (capture.py) fitted again with this tree's
code under VARIANT (base: as the code is; predict: no fit, the geometric branch's prediction; NAME=VALUE,...: FitSettings
fields; ring=R: the pixels within R px of each fitted mask's edge, both sides, unsure; sides=R: the same along its left and right edges only, in each row), each fitted vehicle matched to the ground-truth car of largest mask IoU (an oracle, for scoring only): yaw
error, length / distance ratios, template, the mask's IoU / recall / precision with its car. Prints a summary."""
import glob
import json
import math
import sys

import numpy as np
import torch
import torch.nn.functional as F

import sdn3d.proposal_fit as pf
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings

tree, cap, variant, out = sys.argv[1:5]
records = index_records(read_frames(tree))
torch.set_num_threads(1)
kw, ring = {}, 0
for v in variant.split(","):
    if v in ("base", "predict"): continue
    k, val = v.split("=")
    if k == "ring": ring = int(val); continue
    if k == "sides": ring = -int(val); continue
    kw[k] = type(getattr(FitSettings(), k))(val) if not isinstance(getattr(FitSettings(), k), bool) else val == "true"
settings = FitSettings(**kw)


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


rows = []
for f in sorted(glob.glob(f"{cap}/*.pt")):
    c = torch.load(f, weights_only=False)
    if variant == "predict":
        geometry, fits = c["geometry"], [None] * len(c["rows"])
    else:
        if ring:
            m, r = c["masks"][:, None].float(), abs(ring)
            k, p = ((2 * r + 1, 2 * r + 1), (r, r)) if ring > 0 else ((1, 2 * r + 1), (0, r))
            edge = (F.max_pool2d(m, k, 1, p) > 0) & ~(-F.max_pool2d(-m, k, 1, p) > 0)
            c["unsure"] = c["unsure"] | edge[:, 0]
        geometry, fits = pf.fit_proposals(c["intr"], c["masks"], c["ids"], c["rows"], c["geometry"], settings,
                                          c["appearance"], c["unsure"], c["classes"])
    _, w, var, fr = c["source"].split("/")
    truth = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects
    template, dims, ry, location, _ = geometry
    for k, r in enumerate(c["rows"].tolist()):
        P = c["masks"][r]
        inter = (P[None] & truth.mask).flatten(1).sum(1).float(); uni = (P[None] | truth.mask).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1); t = int(iou.argmax())
        if float(iou[t]) < 0.3 or int(truth.template_id[t]) < 0 or int(template[r]) < 0: continue
        rows.append({"src": c["source"], "id": int(c["ids"][r]), "px": int(P.sum()), "iou": float(iou[t]),
                     "recall": float(inter[t] / truth.mask[t].sum()), "precision": float(inter[t] / P.sum()),
                     "fit_iou": None if fits[k] is None else fits[k].iou,
                     "hyp": None if fits[k] is None else fits[k].hypothesis,
                     "yaw_err": math.degrees(wrap(float(ry[r]) - float(truth.ry[t]))),
                     "tpl": [int(template[r]), int(truth.template_id[t])],
                     "dist_ratio": float(location[r].norm() / truth.location[t].norm()),
                     "len_ratio": float(dims[r, 0] / truth.dims[t, 0]),
                     "true_alpha": math.degrees(wrap(float(truth.ry[t]) - math.atan2(float(truth.location[t, 0]), float(truth.location[t, 2]))))})
json.dump(rows, open(out, "w"), indent=0)
ye = np.array([abs(r["yaw_err"]) for r in rows]); lr = np.array([r["len_ratio"] / r["dist_ratio"] for r in rows])
dr = np.array([r["dist_ratio"] for r in rows]); tp = np.array([r["tpl"][0] == r["tpl"][1] for r in rows])
print(f"{variant} {cap}: n {len(rows)} yaw 20-90 {int(((ye > 20) & (ye <= 90)).sum())} flip {int((ye > 90).sum())} "
      f"median |yaw| {np.median(ye):.1f} length off {int(((lr < 0.87) | (lr > 1.15)).sum())} "
      f"median |log len| {np.median(abs(np.log(lr))):.3f} median |log dist| {np.median(abs(np.log(dr))):.3f} template {tp.mean():.2f}")
