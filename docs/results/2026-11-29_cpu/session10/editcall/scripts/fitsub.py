# ruff: noqa: E402, E501, E701, E702
"""fitsub.py INPUTS N REPEATS: CPU s of the fit of the first N captured objects, parts 1 and 2 in turn, one thread."""
import sys
import time

import torch

torch.set_num_threads(1)
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False)); n = int(sys.argv[2])
a = {k: (v[:n] if isinstance(v, torch.Tensor) else v) for k, v in a.items()}
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
res = {1: [], 2: []}
for _i in range(int(sys.argv[3])):
    for p in (1, 2):
        t = time.process_time(); fit_to_masks(masks, boxes, intr, settings=FitSettings(parts=p), **a); res[p].append(round(time.process_time() - t, 3))
print("n", n, {p: (sorted(v)[len(v) // 2], v) for p, v in res.items()})
