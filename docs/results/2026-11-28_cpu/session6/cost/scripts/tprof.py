# ruff: noqa: E402, E501, E701, E702
"""torch.profiler op table of one fit (1 thread) on captured inputs."""
import sys

import torch

torch.set_num_threads(1)
from torch.profiler import ProfilerActivity, profile

from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False)); masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
s = FitSettings(cull_backfaces=False)
fit_to_masks(masks, boxes, intr, settings=s, **a)
with profile(activities=[ProfilerActivity.CPU]) as prof:
    fit_to_masks(masks, boxes, intr, settings=s, **a)
print(prof.key_averages().table(sort_by="self_cpu_time_total", row_limit=30))
