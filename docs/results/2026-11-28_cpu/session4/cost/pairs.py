# ruff: noqa: E402, E501, E701, E702  (a one-off record script, kept as it ran)
import sys

import torch

torch.set_num_threads(1)
import sdn3d.render.soft as soft
from sdn3d.geometric.fit import FitSettings, fit_to_masks

a = dict(torch.load(sys.argv[1], weights_only=False))
kv = dict(x.split("=", 1) for x in sys.argv[2:])
s = FitSettings(**{k: type(getattr(FitSettings(), k))(v) for k, v in kv.items()})
log = []
wc = soft._window_chunks


def w(bw, bh, budget):
    o, ch = wc(bw, bh, budget)
    log.append((len(bw), len(ch), sum((hi - lo) * h * ww for lo, hi, h, ww in ch), float((bw * bh).sum())))
    return o, ch


soft._window_chunks = w
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
fit_to_masks(masks, boxes, intr, settings=s, **a)
for i in (0, 1, 12, 13, 14, 30, 31):
    if i < len(log):
        print(
            i,
            "faces",
            log[i][0],
            "chunks",
            log[i][1],
            "pairs %.2fM" % (log[i][2] / 1e6),
            "box pairs %.2fM" % (log[i][3] / 1e6),
        )
print("calls", len(log), "total pairs %.1fM" % (sum(l[2] for l in log) / 1e6))
