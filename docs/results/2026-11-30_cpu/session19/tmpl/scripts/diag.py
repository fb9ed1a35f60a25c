# ruff: noqa: E402, E501, E701, E702
"""diag.py TREE CAPTURE_DIR OUT.json [NAME=VALUE+...]: the proposal fits captured by session 18 tierule's capture.py
(its arguments to sdn3d.proposal_fit.fit_proposals; the 10th, the branch's template belief, is kept for the record
only) fitted again with this tree's code (FitSettings from the optional NAME=VALUE list), with the fit's stages
watched: per car the coarse search's best loss of every template, the fine stage's hypotheses (template, final
loss, its silhouette part, size, yaw, the appearance's belief), the winner, and the ground-truth car of largest mask
IoU (>= 0.3; the truth is an oracle, used only to score): its template, size and yaw."""
import glob
import json
import math
import sys

import torch

import sdn3d.geometric.fit as gf
import sdn3d.proposal_fit as pf
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records

tree, cap, out = sys.argv[1:4]
fields = dict(kv.split("=") for kv in sys.argv[4].split("+")) if len(sys.argv) > 4 else {}
base = gf.FitSettings()
settings = gf.FitSettings(**{k: type(getattr(base, k))(v) for k, v in fields.items()})
records = index_records(read_frames(tree))
torch.set_num_threads(1)
W = {}
orig_stage, orig_search, orig_choose, orig_rep = gf._stage, gf._search, gf._choose, gf.reprojection_error


def stage(bank, template, *a, **k):
    values, loss = orig_stage(bank, template, *a, **k)
    if k.get("with_ffd"): W["fine"] = (template.clone(), values, loss.clone(), W["last_sil"])
    return values, loss


def search(bank, template, *a, **k):
    values, loss = orig_search(bank, template, *a, **k)
    W["coarse"] = (template.clone(), loss.clone())
    return values, loss


def choose(loss, belief, ry, s):
    idx = orig_choose(loss, belief, ry, s)
    W["choose"] = (loss.clone(), belief.clone(), ry.clone(), idx.clone())
    return idx


def rep(*a, **k):
    r = orig_rep(*a, **k)
    if not torch.is_grad_enabled(): W["last_sil"] = r.detach().clone()
    return r


gf._stage, gf._search, gf._choose, gf.reprojection_error = stage, search, choose, rep


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


cars = []
for f in sorted(glob.glob(f"{cap}/*.pt")):
    c = torch.load(f, weights_only=False)
    _, w, var, fr = c["source"].split("/")
    truth = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects
    W.clear()
    geometry, recs = pf.fit_proposals(c["intr"], c["masks"], c["ids"], c["rows"], c["geometry"], settings,
                                      c["appearance"], c["unsure"], c["classes"])
    n = len(c["rows"])
    ct, cl = W["coarse"]; ft, fv, fl, fsil = W["fine"]; _, belief, fry, idx = W["choose"]
    per, hyps = len(ct) // n, len(ft) // n
    for k, r in enumerate(c["rows"].tolist()):
        P = c["masks"][r]
        inter = (P[None] & truth.mask).flatten(1).sum(1).float(); uni = (P[None] | truth.mask).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1); t = int(iou.argmax())
        if float(iou[t]) < 0.3 or int(truth.template_id[t]) < 0: continue
        coarse = {}
        for j in range(k * per, (k + 1) * per):
            tp, lv = int(ct[j]), float(cl[j])
            coarse[tp] = min(coarse.get(tp, math.inf), lv)
        hs = []
        for j in range(k * hyps, (k + 1) * hyps):
            hs.append({"tpl": int(ft[j]), "loss": float(fl[j]), "sil": float(fsil[j]), "dims": [round(float(v), 3) for v in fv["dims"][j]],
                       "yaw_err": math.degrees(wrap(float(fv["ry"][j]) - float(truth.ry[t]))),
                       "belief": float(belief[k, j - k * hyps])})
        template, dims, ry, location, _ = geometry
        cars.append({"src": c["source"], "id": int(c["ids"][r]), "px": int(P.sum()), "iou": float(iou[t]),
                     "class": c["classes"][r], "truth_tpl": int(truth.template_id[t]),
                     "truth_dims": [round(float(v), 3) for v in truth.dims[t]],
                     "pred_tpl": int(c["geometry"][0][r]), "pred_dims": [round(float(v), 3) for v in c["geometry"][1][r]],
                     "coarse": {str(a): (b if math.isfinite(b) else None) for a, b in coarse.items()},
                     "hyps": hs, "win": int(idx[k]), "fit_tpl": int(template[r]), "hyp": recs[k].hypothesis,
                     "yaw_err": math.degrees(wrap(float(ry[r]) - float(truth.ry[t]))),
                     "len_ratio": float(dims[r, 0] / truth.dims[t, 0]),
                     "dist_ratio": float(location[r].norm() / truth.location[t].norm())})
    print(c["source"], n, flush=True)
with open(out + ".tmp", "w") as fh:
    json.dump(cars, fh)
import os

os.replace(out + ".tmp", out)
