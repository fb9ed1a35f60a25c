# ruff: noqa: E402, E501, E701, E702

import torch

from sdn3d.geometric.predict import GeometricPredictor

torch.set_num_threads(1)
p = GeometricPredictor.from_checkpoint("/tmp/s30/demo/outputs/demo/runs/geometric/checkpoints/inference.pt")
net = p.net
torch.manual_seed(0)
N = 12
import inspect

print(inspect.signature(net.forward))
# find crop size
crop = torch.rand(N, 3, 64, 64) if True else None
try:
    box = torch.rand(N, 4) * 300; box[:, 2:] += box[:, :2]
    K = torch.tensor([725., 725., 620., 187.]).expand(N, 4).clone()
    out = net(crop, box, K)
except Exception as e:
    print("err", e); raise
def rows(idx, chunk=None):
    c, b, k = crop[idx], box[idx], K[idx]
    if chunk is None:
        return {kk: v for kk, v in net(c, b, k).items()}
    outs = []
    n = len(idx)
    for s in range(0, n, chunk):
        cc, bb, kk = c[s:s+chunk], b[s:s+chunk], k[s:s+chunk]
        m = cc.shape[0]
        if m < chunk:
            pad = [0] * (chunk - m)
            cc, bb, kk = (torch.cat([t, t[pad]]) for t in (cc, bb, kk))
        o = net(cc, bb, kk)
        outs.append({key: v[:m] for key, v in o.items()})
    return {key: torch.cat([o[key] for o in outs]) for key in outs[0]}
with torch.no_grad():
    for chunk in (None, 4, 1):
        diffs = 0; tot = 0
        ref = rows(list(range(N)), chunk)
        for n in range(1, N):
            sub = list(range(n))  # first n rows
            o = rows(sub, chunk if chunk else (4 if n < 4 else None))
            for key in ref:
                d = (o[key] != ref[key][:n]).any(dim=tuple(range(1, o[key].dim()))) if o[key].dim() > 1 else (o[key] != ref[key][:n])
                diffs += int(d.sum()); tot += n
            # shuffled order
        perm = list(reversed(range(N)))
        o = rows(perm, chunk)
        pd = sum(int(((o[key] != ref[key][perm]).reshape(N, -1).any(1)).sum()) for key in ref)
        print("chunk", chunk, "rows differing over prefixes:", diffs, "of", tot, "| reversed order:", pd)
import time

for N2 in (4, 10, 30):
    c = torch.rand(N2, 3, 64, 64); b = torch.rand(N2, 4) * 300; b[:, 2:] += b[:, :2]; k = torch.tensor([725., 725., 620., 187.]).expand(N2, 4).clone()
    crop, box, K = c, b, k
    with torch.no_grad():
        for chunk in (None, 4):
            ts = []
            for _r in range(7):
                t = time.perf_counter(); rows(list(range(N2)), chunk); ts.append(time.perf_counter() - t)
            print(N2, chunk, "median ms", round(sorted(ts)[3] * 1000, 1))
