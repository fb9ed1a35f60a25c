# ruff: noqa: E402, E501, E701, E702, UP031
"""count.py TREE CACHE OUT.json: per fitted semantic proposal (vehicle, fit record) in the cached de-rendered scenes,
the matched ground-truth object (max mask IoU, oracle, for measurement only), the mask bottom rows, and the fit's
relative distance error."""
import json
import os
import sys

import numpy as np
import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records

tree, cache, out = sys.argv[1:4]
records = index_records(read_frames(tree))
rows = []
for line in open(os.path.join(cache, "keys.txt")):
    k, f = line.rsplit(" ", 1)
    w, var, fr = k.split("_")[:3]
    if "semantic" not in k.lower(): continue
    scene = torch.load(os.path.join(cache, f.strip()), weights_only=False)
    gt = scene_from_frame(records[(w, var, int(fr))], (312, 96))
    fits = {x["id"]: x for x in scene.meta.get("fits", [])}
    gm = gt.objects.mask
    for i, iid in enumerate(scene.objects.instance_id.tolist()):
        if iid not in fits or fits[iid]["fit_iou"] is None: continue
        m = scene.objects.mask[i]
        inter = (gm & m).flatten(1).sum(1).float(); uni = (gm | m).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1); g = int(iou.argmax())
        if iou[g] < 0.2: continue
        ys = m.any(1).nonzero().flatten(); gys = gm[g].any(1).nonzero().flatten()
        zt, zf = float(gt.objects.location[g, 2]), float(scene.objects.location[i, 2])
        rows.append({"key": f"{w}/{var} {fr}", "id": iid, "iou": round(float(iou[g]), 3), "bottom": int(ys.max()), "gt_bottom": int(gys.max()),
                     "top": int(ys.min()), "gt_top": int(gys.min()), "z_true": round(zt, 2), "z_fit": round(zf, 2), "z_err": round((zf - zt) / zt, 3),
                     "fit_iou": fits[iid]["fit_iou"], "px": int(m.sum()), "gt_px": int(gm[g].sum())})
json.dump(rows, open(out, "w"), indent=0)
r = rows
miss = [x for x in r if x["gt_bottom"] - x["bottom"] >= max(2, 0.15 * (x["gt_bottom"] - x["gt_top"] + 1))]
print(tree, "fitted semantic proposals", len(r), "missing bottom (>=max(2px,15% of height))", len(miss))
if r:
    print(" median z err all %+.3f ; missing %+.3f ; rest %+.3f" % (np.median([x["z_err"] for x in r]), np.median([x["z_err"] for x in miss]) if miss else np.nan, np.median([x["z_err"] for x in r if x not in miss])))
    print(" z err > 30%%: all %d, missing %d" % (sum(x["z_err"] > 0.3 for x in r), sum(x["z_err"] > 0.3 for x in miss)))
