# ruff: noqa: E402, E501, E701, E702
"""Fit CPU seconds under chunk costs given on the command line, alternating, R rounds."""
import sys
import time

import torch

torch.set_num_threads(1)
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False)); masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
R = int(sys.argv[2]); Cs = [int(c) for c in sys.argv[3:]]
fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
res = {c: [] for c in Cs}
for _ in range(R):
    for c in Cs:
        soft._CHUNK_COST = c; t = time.process_time(); r = fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a); res[c].append(round(time.process_time() - t, 3))
print(res)
