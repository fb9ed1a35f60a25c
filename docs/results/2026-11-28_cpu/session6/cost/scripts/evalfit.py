# ruff: noqa: E402, E501, E701, E702, E401, E731, F401
"""Run fit_to_masks on captured inputs (capture.py) and score it against the truth; per-object JSON + summary.

    python evalfit.py CAPTURE.pt OUT.json [KEY=VALUE ...]   (FitSettings overrides)
"""
import json
import math
import sys
import time

import numpy as np
import torch

torch.set_num_threads(1)
import os

import sdn3d.geometric.fit as fm
from sdn3d.geometric.fit import FitSettings, fit_to_masks
from sdn3d.math3d.transforms import bottom_to_center
from sdn3d.meshes.bank import default_bank
from sdn3d.render import RasterSettings, rasterize_meshes
from sdn3d.render.objects import pose_meshes

if os.environ.get("VARIANT") == "pertemplate":  # survivors: the best start of each template (then the rest by loss)
    _orig_stage = fm._stage
    def _search(bank, template, start, dims0, ry0, mask, ign, K, per, settings, height):
        steps, survivors = settings.coarse_steps, settings.coarse_survivors
        first = steps // 3 if 0 < survivors < per and steps >= 3 else steps
        values, loss = fm._stage(bank, template, start, dims0, ry0, mask, ign, K, settings.coarse_size, first, settings, with_ffd=False, height=height)
        if first == steps:
            return values, loss
        n = loss.shape[0] // per
        t = len(bank); y = per // t
        per_t = loss.view(n, t, y)
        best_y = per_t.argmin(2)  # (n, t)
        firsts = torch.arange(t)[None] * y + best_y  # index within per
        # rank templates by their best loss; take min(survivors, t) templates' best starts, fill with next best
        tl = per_t.amin(2)
        order = tl.argsort(1)[:, :min(survivors, t)]
        chosen = firsts.gather(1, order)
        if survivors > t:
            mark = torch.zeros(n, per, dtype=torch.bool); mark.scatter_(1, chosen, True)
            rest = torch.where(mark, torch.full_like(loss.view(n, per), float("inf")), loss.view(n, per)).topk(survivors - t, dim=1, largest=False).indices
            chosen = torch.cat([chosen, rest], 1)
        rows = (chosen + torch.arange(n)[:, None] * per).flatten()
        rest, rest_loss = fm._stage(bank, template[rows], {k: v[rows] for k, v in values.items()}, dims0[rows], ry0[rows], mask[rows], ign[rows], K[rows], settings.coarse_size, steps - first, settings, with_ffd=False, height=height)
        for k, v in rest.items():
            values[k][rows] = v
        loss = torch.full_like(loss, float("inf")).index_copy(0, rows, rest_loss)
        return values, loss
    fm._search = _search
frames = torch.load(sys.argv[1], weights_only=False)[::int(os.environ.get("STRIDE", "1"))]
kv = dict(a.split("=", 1) for a in sys.argv[3:])
base = FitSettings()
def conv(k, v):
    d = getattr(base, k)
    if isinstance(d, bool): return v.lower() in ("1", "true")
    return type(d)(v) if d is not None else float(v)
settings = FitSettings(**{k: conv(k, v) for k, v in kv.items()})
rows, cpu = [], 0.0
for f in frames:
    a = dict(f["args"]); masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
    torch.manual_seed(0)
    t0 = time.process_time()
    r = fit_to_masks(masks, boxes, intr, settings=settings, **a)
    cpu += time.process_time() - t0
    center = bottom_to_center(r.location, r.dims[:, 1])
    verts, faces = pose_meshes(default_bank(), r.template, r.dims, r.ry, center, r.phi)
    drawn = rasterize_meshes(verts, faces, intr.matrix().float(), RasterSettings(tuple(masks.shape[-2:]))).mask
    for j, iid in enumerate(f["ids"]):
        d = float(r.ry[j] - f["true_ry"][j])
        yaw = abs(math.degrees(math.atan2(math.sin(d), math.cos(d))))
        keep = ~f["others"][j]
        dr, tg = drawn[j] & keep, f["true_mask"][j] & keep
        u = int((dr | tg).sum())
        rows.append({"frame": f["key"], "id": iid, "yaw_deg": yaw,
                     "template_ok": int(r.template[j]) == int(f["true_template"][j]),
                     "dist": abs(math.log(float(center[j].norm()) / float(f["true_center"][j].norm()))),
                     "scale": float((r.dims[j] - f["true_dims"][j]).norm()),
                     "sil_iou": int((dr & tg).sum()) / u if u else 0.0, "fit_iou": float(r.iou[j]),
                     "hyp": int(r.hypothesis[j])})
yaw = np.array([x["yaw_deg"] for x in rows])
summary = {"settings": kv, "n": len(rows), "fit_cpu_s": round(cpu, 1), "yaw_median": round(float(np.median(yaw)), 2),
           "yaw_p90": round(float(np.percentile(yaw, 90)), 1), "flips": int((yaw > 90).sum()),
           "template_pct": round(100 * np.mean([x["template_ok"] for x in rows]), 1),
           "dist_x1e2": round(100 * float(np.median([x["dist"] for x in rows])), 2),
           "scale_m": round(float(np.median([x["scale"] for x in rows])), 3),
           "sil_iou": round(float(np.mean([x["sil_iou"] for x in rows])), 4),
           "fit_iou": round(float(np.mean([x["fit_iou"] for x in rows])), 4)}
print(json.dumps(summary))
json.dump({"summary": summary, "objects": rows}, open(sys.argv[2], "w"))
