# ruff: noqa: E401, E402, E501, E701, E702, B023, F401, F841, I001
"""A probe of one cost this helper looked at and did not cut (README section 4); run from the worktree with
PYTHONPATH=src, threads 1."""
import time, torch
torch.set_num_threads(1)
g = torch.Generator().manual_seed(1)
def knn(q, e, k, chunk):
    return torch.cat([torch.cdist(c, e).topk(k, largest=False).indices for c in q.split(chunk)])
def t(f, n=5):
    ts = []
    for _ in range(n):
        t0 = time.process_time(); f(); ts.append(time.process_time() - t0)
    return round(1000 * min(ts), 1)
for Q, E, k in ((8000, 1500, 4), (8000, 1500, 16), (3000, 600, 4), (20000, 1500, 4)):
    q = torch.randn(Q, 6, generator=g, dtype=torch.float64).float(); e = torch.randn(E, 6, generator=g, dtype=torch.float64).float()
    base = knn(q, e, k, 8192)
    line = [Q, E, k, "8192:", t(lambda: knn(q, e, k, 8192))]
    for ch in (2048, 512, 128):
        line += [f"{ch}:", t(lambda: knn(q, e, k, ch)), torch.equal(knn(q, e, k, ch), base)]
    d = torch.cdist(q, e)
    line += ["cdist only", t(lambda: torch.cdist(q, e)), "topk only", t(lambda: d.topk(k, largest=False))]
    print(*line)
