# ruff: noqa: E402, E501, E701, E702
"""CPU seconds and results of fit_to_masks on captured inputs, settings as key=value; prints JSON."""
import json
import sys
import time

import torch

torch.set_num_threads(1)
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False)); R = int(sys.argv[2])
kv = dict(x.split("=", 1) for x in sys.argv[3:])
conv = {bool: lambda v: v in ("1", "true", "True"), int: int, float: float, str: str}
d = FitSettings()
s = FitSettings(**{k: conv[type(getattr(d, k))](v) for k, v in kv.items()})
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
cpu = []
for _ in range(R):
    t = time.process_time(); r = fit_to_masks(masks, boxes, intr, settings=s, **a); cpu.append(round(time.process_time() - t, 3))
print(json.dumps({"kv": kv, "cpu": cpu, "iou": [round(float(v), 3) for v in r.iou], "ry_deg": [round(float(v) * 57.3, 1) for v in r.ry], "tmpl": r.template.tolist(), "mean_iou": round(float(r.iou.mean()), 4)}))
