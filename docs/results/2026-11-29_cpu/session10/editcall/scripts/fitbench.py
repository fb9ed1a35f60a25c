# ruff: noqa: E402, E501, E701, E702
"""fitbench.py INPUTS THREADS REPEATS [PARTS [OUT.pt]]: the fit on captured inputs (belief: cos to the start, so the mirror runs); CPU and wall s each time."""
import sys
import time

import torch

torch.set_num_threads(int(sys.argv[2]))
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
first = torch.where(torch.isfinite(a["start_ry"]), a["start_ry"], torch.full_like(a["start_ry"], -1.5708))
def belief(ry):
    return torch.cos(ry - first[:, None])
settings = FitSettings(parts=int(sys.argv[4])) if len(sys.argv) > 4 else FitSettings()
for _i in range(int(sys.argv[3])):
    t = time.process_time(); w = time.perf_counter()
    r = fit_to_masks(masks, boxes, intr, settings=settings, yaw_belief=belief, **a)
    print("threads", sys.argv[2], "parts", getattr(settings, "parts", 1), "fit cpu", round(time.process_time() - t, 3), "wall", round(time.perf_counter() - w, 3), flush=True)
if len(sys.argv) > 5:
    torch.save({k: getattr(r, k) for k in ("template", "dims", "ry", "location", "phi", "iou", "loss", "hypothesis")}, sys.argv[5])
