# ruff: noqa: B023, E402, E501, E701, E702, E731
"""diag.py TREE CACHE_DIR [OUT.json]: every fitted semantic proposal of the cached de-rendered source scenes, matched to
the ground-truth object of largest mask IoU (oracle, for measurement only): how far its mask stops above the car's
visible bottom (px, 312x96), the fit's relative distance error, and the fitted size against the truth's."""
import glob
import json
import sys

import numpy as np
import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records

tree, cache = sys.argv[1:3]
records = index_records(read_frames(tree))
rows = []
for f in sorted(glob.glob(cache + "/*.pt")):
    scene = torch.load(f, weights_only=False)
    if scene.meta.get("proposals") != "semantic": continue
    _, w, var, fr = scene.meta["source"].split("/")
    gt = scene_from_frame(records[(w, var, int(fr))], (312, 96))
    fits = {x["id"]: x for x in scene.meta.get("fits", [])}
    gm = gt.objects.mask
    for i, iid in enumerate(scene.objects.instance_id.tolist()):
        if iid not in fits or fits[iid]["fit_iou"] is None: continue
        m = scene.objects.mask[i]
        inter = (gm & m).flatten(1).sum(1).float(); uni = (gm | m).flatten(1).sum(1).float()
        iou = inter / uni.clamp_min(1); g = int(iou.argmax())
        if iou[g] < 0.2: continue
        ys, xs = m.any(1).nonzero().flatten(), m.any(0).nonzero().flatten()
        gys, gxs = gm[g].any(1).nonzero().flatten(), gm[g].any(0).nonzero().flatten()
        zt, zf = float(gt.objects.location[g, 2]), float(scene.objects.location[i, 2])
        rows.append({"key": f"{w}/{var} {fr}", "id": iid, "var": var, "iou": float(iou[g]),
                     "cut": int(gys.max() - ys.max()), "top": int(ys.min() - gys.min()), "gt_h": int(gys.max() - gys.min() + 1),
                     "width": (int(xs.max() - xs.min() + 1)) / (int(gxs.max() - gxs.min() + 1)),
                     "z_true": zt, "z_err": (zf - zt) / zt,
                     "scale": float((scene.objects.dims[i] / gt.objects.dims[g]).log().mean().exp()),
                     "dims": [round(float(v), 2) for v in scene.objects.dims[i]], "gt_dims": [round(float(v), 2) for v in gt.objects.dims[g]],
                     "hyp": fits[iid]["hypothesis"], "fit_iou": fits[iid]["fit_iou"]})
if len(sys.argv) > 3: json.dump(rows, open(sys.argv[3], "w"), indent=0)
for var in sorted({r["var"] for r in rows}):
    v = [r for r in rows if r["var"] == var]
    for name, sel in (("cut>=2", [r for r in v if r["cut"] >= 2]), ("uncut", [r for r in v if r["cut"] < 2])):
        if not sel: continue
        a = lambda k: np.array([r[k] for r in sel])
        print(f"{var:6s} {name:7s} n {len(sel):3d}: z err median {np.median(a('z_err')):+.3f} mean|.| {np.abs(a('z_err')).mean():.3f}; "
              f"scale median {np.median(a('scale')):.3f}; mask width/gt {np.median(a('width')):.2f}; top diff {np.median(a('top')):+.1f}; cut {np.median(a('cut')):+.1f} px")
