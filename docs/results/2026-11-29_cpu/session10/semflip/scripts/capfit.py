# ruff: noqa: E402, E501, E701, E702
"""capfit.py TREE OUT.pt PROPOSALS [VARIATION]: de-render every rotate-entry source frame (of VARIATION, e.g. clone)
with the bench's fit (default FitSettings, session-5 demo weights, 312x96) and record per proposal vehicle: the
lamp cue's input (crop * sure mask, sure mask), the appearance, the fit's fine hypotheses (loss, belief, yaw, the
chosen one), its mask, the best-matching ground-truth object (oracle, for scoring only: true yaw, mask, IoU)."""
import os
import sys

import torch

import sdn3d.geometric.fit as F
import sdn3d.geometric.predict as P
import sdn3d.proposal_fit as PF
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import Models, derender
from sdn3d.evaluation.edit_benchmark import edit_kind, index_records
from sdn3d.geometric.fit import FitSettings

torch.set_num_threads(1)
tree, out, prop = sys.argv[1:4]
var = sys.argv[4] if len(sys.argv) > 4 else None
R = "/tmp/s5data/lead/demo/runs"
models = Models.from_checkpoints(f"{R}/semantic/checkpoints/inference.pt", f"{R}/geometric/checkpoints/inference.pt", f"{R}/textural/checkpoints/inference.pt")
size = (312, 96)
entries = load_edit_benchmark(os.path.join(tree, "vkitti_edit_benchmark.json"))
recs = index_records(read_frames(tree))
frames = sorted({(e.world, e.variation, e.source_frame) for e in entries if edit_kind(e) == "rotate" and (var is None or e.variation == var)})
CALL, CH, REQ = {}, [], []
orig = P.GeometricPredictor.predict
def predict(self, crop, mask, box, intrinsics, *a, lamp_mask=None, **k):
    o = orig(self, crop, mask, box, intrinsics, *a, lamp_mask=lamp_mask, **k)
    lm = mask if lamp_mask is None else lamp_mask
    CALL.update(seen=(crop * lm).half(), lamps=(lm > 0.5), box=box.clone(), out={kk: v.detach().cpu() for kk, v in o.items() if kk in ("net_ry", "ray", "ry", "lamp_present", "lamp_usable", "lamp_offset", "front_present", "front_usable", "front_offset")})
    return o
P.GeometricPredictor.predict = predict
orig_choose = F._choose
def choose(loss, belief, ry, settings):
    idx = orig_choose(loss, belief, ry, settings)
    CH.append({"loss": loss.clone(), "belief": belief.clone(), "ry": ry.clone(), "index": idx.clone()})
    return idx
F._choose = choose
orig_req = PF.proposal_request
def preq(masks, rows, *a, **k):
    r = orig_req(masks, rows, *a, **k)
    REQ.append({"rows": rows.clone(), "ignore": r.ignore.clone() if r.ignore is not None else None})
    return r
PF.proposal_request = preq
import sdn3d.derender as D

D.fit_proposals.__globals__["proposal_request"] = preq

rows = []
for key in frames:
    rec = recs[key]
    src = load_frame(rec, size, semantic=False, instances=False)
    CALL.clear(); CH.clear(); REQ.clear()
    scene = derender(src.image, src.intrinsics, models, prop, ground_truth(rec, size), min_pixels=64, fit=FitSettings(), photo=frame_photo(rec, size))
    oracle = scene_from_frame(rec, size).objects
    geo = (oracle.template_id >= 0).nonzero().flatten()
    obj = scene.objects
    if not CH or not REQ: print(key, "no fit", flush=True); continue
    fitrows = REQ[0]["rows"]
    ch = CH[0]
    # predictor rows: objects with >= min_pixels and wide boxes, in order; map by box
    pbox = CALL["box"].cpu().float()
    from sdn3d.image_ops import mask_boxes, pixel_centre_boxes
    allbox = pixel_centre_boxes(mask_boxes(obj.mask)).float()
    for k, r in enumerate(fitrows.tolist()):
        m = obj.mask[r]
        inter = (m[None] & oracle.mask[geo]).flatten(1).sum(1).float(); uni = (m[None] | oracle.mask[geo]).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1)
        if not len(iou) or iou.max() < 0.3: continue
        j = int(iou.argmax()); g = int(geo[j])
        pi = ((pbox - allbox[r]).abs().sum(1) < 1e-3).nonzero().flatten()
        pi = int(pi[0]) if len(pi) else None
        rows.append({"key": key, "id": int(obj.instance_id[r]), "gt_id": int(oracle.instance_id[g]), "iou": float(iou[j]),
                     "mask": m.clone(), "all_masks": obj.mask, "row": r, "var": key[1], "gt_mask": oracle.mask[g].clone(), "ignore": REQ[0]["ignore"][k].clone() if REQ[0]["ignore"] is not None else None,
                     "true_ry": float(oracle.ry[g]), "true_loc": oracle.location[g].tolist(), "fit_ry": float(obj.ry[r]), "fit_loc": obj.location[r].tolist(),
                     "loss": ch["loss"][k], "belief": ch["belief"][k], "hyp_ry": ch["ry"][k], "index": int(ch["index"][k]),
                     "fit": [f for f in scene.meta["fits"] if f["id"] == int(obj.instance_id[r])][0],
                     **({"seen": CALL["seen"][pi].cpu(), "lamps": CALL["lamps"][pi].cpu(), **{kk: v[pi] for kk, v in CALL["out"].items()}} if pi is not None else {})})
    print(key, len(rows), flush=True)
torch.save(rows, out)
