# ruff: noqa: E402, E501, E701, E702
"""Capture the face boxes of fit renders, then compare chunking rules: pairs computed, chunks."""
import sys

import torch

torch.set_num_threads(1)
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False)); masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
caps = []
wc = soft._window_chunks
def chunks(w, h, budget):
    caps.append((w.clone(), h.clone(), budget)); return wc(w, h, budget)
soft._window_chunks = chunks
fit_to_masks(masks, boxes, intr, settings=FitSettings(), **a)
def cost(fn, C):
    P = N = 0
    for w, h, b in caps:
        _, ch = fn(w, h, b); N += len(ch); P += sum((hi - lo) * x * y for lo, hi, x, y in ch)
    return P, N, P + C * N
own = sum(int((w * h).sum()) for w, h, _ in caps)
print("calls", len(caps), "own pairs", own)
for C in (8192, 4096, 2048):
    soft._CHUNK_COST = C
    print("CHUNK_COST", C, "pairs, chunks, pairs+8192*chunks", cost(wc, 8192))
