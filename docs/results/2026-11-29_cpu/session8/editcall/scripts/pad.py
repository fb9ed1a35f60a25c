# ruff: noqa: E402, E501, E701, E702
"""Lane padding of the kernel's face groups: window pairs evaluated vs the faces' own box pairs, per kernel call."""
import sys

import torch

torch.set_num_threads(1)
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
tot = [0, 0, 0]
call = soft._call
def timed(kernel, direction, screen, box, *x):
    call(kernel, direction, screen, box, *x)
    if direction != "forward": return
    b = box[(box[:, 2] * box[:, 3]) > 0]
    key = b[:, 3] * 100000 + b[:, 2]
    b = b[torch.argsort(key, stable=True)]
    n = len(b); g = (n + 15) // 16
    pad = torch.zeros(g * 16, 4, dtype=torch.long); pad[:n] = b
    w = pad[:, 2].view(g, 16).amax(1); h = pad[:, 3].view(g, 16).amax(1)
    tot[0] += int((b[:, 2] * b[:, 3]).sum()); tot[1] += int((w * h).sum() * 16); tot[2] += n
soft._call = timed
fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
print("own pairs M", tot[0] / 1e6, "lane pairs M", tot[1] / 1e6, "ratio", tot[1] / tot[0], "faces M", tot[2] / 1e6, "pairs/face", tot[0] / tot[2])
