# ruff: noqa: B007, E401, E501, E702, E731, B023, I001
"""Probe (README section 4): torch sum over a dimension of three against sum3, bit equality and time, threads 1."""
import time, torch
torch.set_num_threads(1)
g = torch.Generator().manual_seed(1)
def t(f, n=15):
    ts = []
    for _ in range(n):
        t0 = time.perf_counter(); f(); ts.append(1e3 * (time.perf_counter() - t0))
    return round(sorted(ts)[n // 4], 3)
def s3(x, dim):
    a, b, c = x.unbind(dim)
    return a + b + c + 0.0
for P in (1, 5, 100, 5000, 60000):
    for dt, it in ((torch.float64, torch.int64), (torch.float32, torch.int32)):
        bary = torch.rand(P, 3, generator=g, dtype=dt); tri = torch.randn(P, 3, 3, generator=g, dtype=dt) * 30
        tri[::5] = -0.0; bary[::3, 1] = -0.0
        x = bary[..., None] * tri
        eq1 = torch.equal(x.sum(1).view(it), s3(x, 1).view(it))
        n = torch.randn(P, 3, generator=g, dtype=dt); n[::4] = -0.0
        y = n * tri[:, 0]
        eq2 = torch.equal(y.sum(-1).view(it), s3(y, -1).view(it))
        eq3 = torch.equal(y.sum(-1, keepdim=True).view(it), s3(y, -1)[:, None].view(it))
        print(P, dt, eq1, eq2, eq3, "mid sum", t(lambda: x.sum(1)), "cols", t(lambda: s3(x, 1)), "last", t(lambda: y.sum(-1)), t(lambda: s3(y, -1)))
