# ruff: noqa: E402, E501, E701, E702
"""Run the fit once on captured inputs with T threads; save its result tensors (identity checks between code versions
and thread counts) and print the fit's CPU seconds."""
import sys
import time

import torch

torch.set_num_threads(int(sys.argv[3]))
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
t = time.process_time(); w = time.perf_counter()
r = fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
print("fit cpu", round(time.process_time() - t, 3), "wall", round(time.perf_counter() - w, 3))
torch.save({k: getattr(r, k) for k in ("template", "dims", "ry", "location", "phi", "iou", "loss", "hypothesis")}, sys.argv[2])
