# ruff: noqa: E402, E501, E701, E702
"""Fit on captured inputs: CPU s of the whole fit and of the kernel calls, pairs per direction; native vs PyTorch path."""
import sys
import time

import torch

torch.set_num_threads(1)
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
mode = sys.argv[2]
if mode == "torch":
    soft.soft_kernel = lambda: None
acc = {"forward": [0.0, 0, 0], "backward": [0.0, 0, 0]}
call = soft._call
def timed(kernel, direction, screen, box, *x):
    t = time.process_time(); call(kernel, direction, screen, box, *x)
    r = acc[direction]; r[0] += time.process_time() - t; r[1] += int((box[:, 2] * box[:, 3]).sum()); r[2] += 1
soft._call = timed
fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
for k in acc: acc[k] = [0.0, 0, 0]
t = time.process_time()
r = fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
print(mode, "fit cpu", round(time.process_time() - t, 3), {k: (round(v[0], 3), v[1] / 1e6, v[2], round(v[0] / max(v[1], 1) * 1e9, 2)) for k, v in acc.items()})
print([(round(float(y), 3)) for y in r.ry[:5]] if hasattr(r, "ry") else type(r))
