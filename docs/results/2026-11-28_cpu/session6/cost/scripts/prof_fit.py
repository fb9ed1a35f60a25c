# ruff: noqa: E402, E501, E701, E702
"""cProfile of fit_to_masks on captured inputs (1 thread)."""
import cProfile
import pstats
import sys
import time

import torch

torch.set_num_threads(1)
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
t = time.process_time()
pr = cProfile.Profile(); pr.enable()
r = fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
pr.disable()
print("cpu", time.process_time() - t)
pstats.Stats(pr).sort_stats("tottime").print_stats(25)
