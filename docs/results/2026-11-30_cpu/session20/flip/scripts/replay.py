# ruff: noqa: E402, E501, E701, E702
"""replay.py TREE CAPTURE_DIR OUT.json [NAME=VALUE+...]: the captured proposal fits (capture.py) fitted again with the
code on the path (FitSettings fields changed as given; none: the defaults), recording what decided each object's end:
the fine stage's hypotheses (their losses, fitted yaws and the appearance's belief in them, as fit._choose sees them),
the winner, and the belief's two parts (the lamps' evidence and the net's bins, facing.facing_belief) at the fitted yaw
and its reverse. Each fitted vehicle is matched to the ground-truth car of largest mask IoU (>= 0.3; the truth is an
oracle, used only to score). diagnose.py reads the JSON."""
import glob
import json
import math
import os
import sys

import torch

import sdn3d.geometric.fit as gf
import sdn3d.proposal_fit as pf
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.facing import BIN_KEYS, FRONT_KEYS
from sdn3d.geometric.lamps import evidence_of
from sdn3d.geometric.model import yaw_distribution

tree, cap, out = sys.argv[1:4]
fields = dict(kv.split("=") for kv in (sys.argv[4].split("+") if len(sys.argv) > 4 else []))
default = gf.FitSettings()
settings = gf.FitSettings(**{k: type(getattr(default, k))(v) for k, v in fields.items()})
records = index_records(read_frames(tree))
torch.set_num_threads(1)
SEEN = {}
_choose = gf._choose


def spy(loss, belief, ry, s, *rest, **kw):
    index = _choose(loss, belief, ry, s, *rest, **kw)
    SEEN.update(loss=loss.clone(), belief=belief.clone(), ry=ry.clone(), index=index.clone())
    return index


gf._choose = spy


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def parts(app, rows, ry):
    """(lamps, net) of facing_belief at yaws ry (K, H) of the appearance's rows."""
    v = {k: t[rows] for k, t in app.values.items()}
    front = tuple(v[k] for k in FRONT_KEYS) if all(k in v for k in FRONT_KEYS) else None
    lamps = evidence_of(v["lamp_present"].bool(), v["lamp_usable"].bool(), v["lamp_offset"], ry - v["ray"][:, None],
                        app.cue, front=front)
    raw = {k: v[k] for k in BIN_KEYS} if all(k in v for k in BIN_KEYS) else None
    net = 2 * yaw_distribution(raw, ry) - 1 if raw is not None else torch.cos(ry - v["net_ry"][:, None])
    return lamps, net, -app.cue.flip_below, v


cars = []
for f in sorted(glob.glob(f"{cap}/*.pt")):
    c = torch.load(f, weights_only=False)
    _, w, var, fr = c["source"].split("/")
    truth = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects
    SEEN.clear()
    geometry, recs = pf.fit_proposals(c["intr"], c["masks"], c["ids"], c["rows"], c["geometry"], settings,
                                      c["appearance"], c["unsure"], c["classes"])
    rows = c["rows"]
    ry_h = SEEN["ry"].double()
    lamps, net, w_net, v = parts(c["appearance"], rows, ry_h)
    for k, r in enumerate(rows.tolist()):
        P = c["masks"][r]
        inter = (P[None] & truth.mask).flatten(1).sum(1).float(); uni = (P[None] | truth.mask).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1); t = int(iou.argmax())
        if float(iou[t]) < 0.3 or int(truth.template_id[t]) < 0: continue
        true_ry = float(truth.ry[t])
        hyps = [{"ry": round(float(ry_h[k, h]), 4), "loss": round(float(SEEN["loss"][k, h]), 5),
                 "belief": round(float(SEEN["belief"][k, h]), 4), "lamps": round(float(lamps[k, h]), 4),
                 "net": round(float(net[k, h]), 4),
                 "err": round(math.degrees(abs(wrap(float(ry_h[k, h]) - true_ry))), 2)} for h in range(ry_h.shape[1])]
        cars.append({"src": c["source"], "id": int(c["ids"][r]), "px": int(P.sum()), "iou": round(float(iou[t]), 3),
                     "class": c["classes"][r], "true_ry": round(true_ry, 4),
                     "true_alpha": round(wrap(true_ry - float(v["ray"][k])), 4),
                     "branch_err": round(math.degrees(abs(wrap(float(c["geometry"][2][r]) - true_ry))), 2),
                     "lamp": [bool(v["lamp_present"][k]), bool(v["lamp_usable"][k]), round(float(v["lamp_offset"][k]), 3)],
                     "front": [bool(v[x][k]) if x != "front_offset" else round(float(v[x][k]), 3) for x in FRONT_KEYS] if all(x in v for x in FRONT_KEYS) else None,
                     "has": bool(c["appearance"].has[r]), "net_weight": w_net,
                     "winner": int(SEEN["index"][k]), "hypothesis": recs[k].hypothesis, "fit_iou": recs[k].iou,
                     "err": round(math.degrees(abs(wrap(float(geometry[2][r]) - true_ry))), 2),
                     "tpl": int(geometry[0][r]), "truth_tpl": int(truth.template_id[t]), "hyps": hyps})
    print(c["source"], len(rows), flush=True)
with open(out + ".tmp", "w") as fh:
    json.dump({"settings": settings.to_dict(), "cars": cars}, fh)
os.replace(out + ".tmp", out)
