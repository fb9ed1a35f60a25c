# ruff: noqa: E402, E501, E701, E702  (a one-off record script, kept as it ran)
"""How early does the coarse search know its final top-`keep`? For each step s and survivors k: the share of objects
whose final top-3 starts are all within the top-k by loss at step s (val13 capture, every 2nd frame)."""

import sys

import torch

torch.set_num_threads(1)
import sdn3d.geometric.fit as fm
from sdn3d.geometric.fit import FitSettings, fit_to_masks

frames = torch.load(sys.argv[1], weights_only=False)[:: int(sys.argv[2])]
hist = []
real = fm.adam_fit


def spy(params, objective, steps, lr):
    h = real(params, objective, steps, lr)
    with torch.no_grad():
        h.append(objective().detach())
    hist.append(h)
    return h


fm.adam_fit = spy
s = FitSettings(fine_steps=0)
res = {}
tot = 0
for f in frames:
    a = dict(f["args"])
    masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
    hist.clear()
    fit_to_masks(masks, boxes, intr, settings=s, **a)
    h = torch.stack(hist[0])  # (13, n*32)
    n = masks.shape[0]
    h = h.view(h.shape[0], n, -1)
    final = h[-1].topk(3, 1, largest=False).indices  # (n, 3)
    tot += n
    for step in (1, 2, 3, 4, 6, 8):
        rank = h[step].argsort(1).argsort(1)  # rank of each start at step
        r = rank.gather(1, final).amax(1)  # worst rank among final top-3
        for k in (3, 4, 6, 8, 12, 16):
            res[(step, k)] = res.get((step, k), 0) + int((r < k).sum())
for step in (1, 2, 3, 4, 6, 8):
    print(step, {k: round(res[(step, k)] / tot, 3) for k in (3, 4, 6, 8, 12, 16)})
print("objects", tot)
