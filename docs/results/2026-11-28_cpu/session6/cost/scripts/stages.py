# ruff: noqa: E402, E501, E701, E702
"""Per-stage CPU seconds, raster calls, chunks and (face, pixel) pairs of fit_to_masks on captured inputs."""
import json
import sys
import time

import torch

torch.set_num_threads(1)
import sdn3d.geometric.fit as fm
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
kv = dict(x.split("=", 1) for x in sys.argv[2:])
conv = {bool: lambda v: v in ("1", "true", "True"), int: int, float: float, str: str}
d = FitSettings(); s = FitSettings(**{k: conv[type(getattr(d, k))](v) for k, v in kv.items()})
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
cur = {}
wc = soft._window_chunks
def chunks(w, h, budget):
    order, ch = wc(w, h, budget)
    cur["chunks"] += len(ch); cur["own"] = cur.get("own", 0) + int((w * h).sum()); cur["pairs"] += sum((hi - lo) * a_ * b_ for lo, hi, a_, b_ in ch); cur["faces"] += len(w); return order, ch
soft._window_chunks = chunks
st = fm._stage; rows = []
def stage(bank, template, start, *x, **k):
    cur.clear(); cur.update(chunks=0, pairs=0, faces=0, own=0); t = time.process_time(); o = st(bank, template, start, *x, **k)
    rows.append({"M": len(template), "size": x[5], "steps": x[6], "cpu": round(time.process_time() - t, 3), **cur}); return o
fm._stage = stage
fit_to_masks(masks, boxes, intr, settings=s, **a)
rows.clear(); t = time.process_time(); fit_to_masks(masks, boxes, intr, settings=s, **a)
print(json.dumps({"kv": kv, "cpu": round(time.process_time() - t, 3), "stages": rows}, indent=0))
