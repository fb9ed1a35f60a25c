# ruff: noqa: E402, E501, E701, E702
import time

import torch

from sdn3d.geometric.predict import MIN_NET_ROWS, GeometricPredictor

torch.set_num_threads(1)
p = GeometricPredictor.from_checkpoint("/tmp/s30/demo/outputs/demo/runs/geometric/checkpoints/inference.pt")
def old(crop, box, intrinsics):
    n = crop.shape[0]
    if 0 < n < MIN_NET_ROWS:
        pad = [0] * (MIN_NET_ROWS - n)
        crop, box, intrinsics = (torch.cat([t, t[pad]]) for t in (crop, box, intrinsics))
        return {k: v[:n] for k, v in p.net(crop, box, intrinsics).items()}
    return p.net(crop, box, intrinsics)
res = {}
with torch.no_grad():
    for N in (3, 10, 30):
        crop = torch.rand(N, 3, 64, 64); box = torch.rand(N, 4) * 300; box[:, 2:] += box[:, :2]
        K = torch.tensor([725., 725., 620., 187.]).expand(N, 4).clone()
        for _r in range(12):
            for name, f in (("new", p._net_rows), ("old", old)):
                t = time.process_time(); f(crop, box, K); res.setdefault((N, name), []).append(time.process_time() - t)
for k, v in sorted(res.items()):
    v = sorted(v); print(k, "median ms", round(v[len(v)//2] * 1000, 1))
