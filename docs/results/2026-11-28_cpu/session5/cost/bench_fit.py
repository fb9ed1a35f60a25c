# ruff: noqa: E401, E402, E501, E701, E702, E731, F401, I001, B023
"""CPU seconds of fit_to_masks on captured dense inputs: total and per stage, median of R repeats."""
import json, statistics, sys, time
import torch
torch.set_num_threads(int(__import__("os").environ.get("NT","1")))
import sdn3d.geometric.fit as fm
from sdn3d.geometric.fit import FitSettings, fit_to_masks
a = dict(torch.load(sys.argv[1], weights_only=False)); R = int(sys.argv[2])
kv = dict(x.split("=", 1) for x in sys.argv[3:])
s = FitSettings(**{k: type(getattr(FitSettings(), k))(v) for k, v in kv.items()})
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
st = []
stage = fm._stage
def timed(*x, **k):
    t = time.process_time(); o = stage(*x, **k); st.append(time.process_time() - t); return o
fm._stage = timed
fit_to_masks(masks, boxes, intr, settings=s, **a)
runs = []
for _ in range(R):
    st.clear(); t = time.process_time(); w = time.perf_counter(); r = fit_to_masks(masks, boxes, intr, settings=s, **a)
    runs.append((time.process_time() - t, list(st), time.perf_counter() - w))
med = sorted(runs)[len(runs) // 2]
print(json.dumps({"kv": kv, "cpu": round(med[0], 3), "stages": [round(x, 3) for x in med[1]], "all": [round(x[0], 3) for x in runs], "wall": [round(x[2], 3) for x in runs],
                  "iou": [round(float(v), 3) for v in r.iou], "ry": [round(float(v), 3) for v in r.ry], "tmpl": r.template.tolist()}))
