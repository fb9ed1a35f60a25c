# ruff: noqa: E402, E501, E701, E702
"""Fit CPU seconds for (chunk_cost, cull_eps, fit settings) variants, alternating, R rounds; and the results."""
import json
import sys
import time

import torch

torch.set_num_threads(1)
import sdn3d.geometric.fit as fm
import sdn3d.render.settings as rs
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False)); masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
R = int(sys.argv[2]); variants = [json.loads(v) for v in sys.argv[3:]]
orig = rs.SoftSilhouetteSettings
def run(v):
    soft._CHUNK_COST = v.get("chunk", 8192)
    eps = v.get("eps", 1e-4)
    fm.SoftSilhouetteSettings = lambda *x, **k: orig(*x, cull_eps=eps, **k)
    s = FitSettings(**v.get("fit", {}))
    t = time.process_time(); r = fit_to_masks(masks, boxes, intr, settings=s, **a); return time.process_time() - t, r
run(variants[0])
res = {i: [] for i in range(len(variants))}; out = {}
for _ in range(R):
    for i, v in enumerate(variants):
        c, r = run(v); res[i].append(round(c, 3)); out[i] = (round(float(r.iou.mean()), 4), r.template.tolist())
for i, v in enumerate(variants): print(v, res[i], sorted(res[i])[len(res[i]) // 2], out[i])
