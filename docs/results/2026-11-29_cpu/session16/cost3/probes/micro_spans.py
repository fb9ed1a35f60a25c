# ruff: noqa: E401, E402, E501, E701, E702, B023, F401, F841, I001
"""A probe of one cost this helper looked at and did not cut (README section 4); run from the worktree with
PYTHONPATH=src, threads 1."""
import time, torch
from sdn3d.render.rasterize import _INSIDE_EPS, _row_spans
torch.set_num_threads(1)
g = torch.Generator().manual_seed(12)
F_, P = 20000, 200000
a, b, c = (torch.randn(F_, 3, generator=g, dtype=torch.float64) for _ in range(3))
pair = torch.randint(0, F_, (P,), generator=g).sort().values
rows = torch.randint(0, 375, (P,), generator=g).double()
width = 1242

def spans_t(aT, bT, cT, rows, width):
    out_first, out_count = None, None
    lower = upper = None
    feasible = None
    for k in range(3):
        ak = aT[k]
        rhs = -_INSIDE_EPS - bT[k] * rows - cT[k]
        flat = ak == 0
        bound = rhs / torch.where(flat, 1.0, ak)
        lo = bound.masked_fill(~(ak > 0), float("-inf"))
        hi = bound.masked_fill(~(ak < 0), float("inf"))
        lower = lo if lower is None else torch.maximum(lower, lo)
        upper = hi if upper is None else torch.minimum(upper, hi)
        o = flat & ~(rhs <= 0)
        feasible = ~o if feasible is None else feasible & ~o
    lower = lower.clamp_(-1.0, width); upper = upper.clamp_(-1.0, width)
    first = torch.ceil(lower).clamp_(min=0).long()
    last = torch.floor(upper).clamp_(max=width - 1).long()
    return first, (last - first + 1).clamp_(min=0) * feasible

def t(f, n=7):
    ts = []
    for _ in range(n):
        t0 = time.process_time(); f(); ts.append(time.process_time() - t0)
    return round(1000 * min(ts), 2)
print("old incl gathers", t(lambda: _row_spans(a[pair], b[pair], c[pair], rows, width)))
aT, bT, cT = a.T.contiguous(), b.T.contiguous(), c.T.contiguous()
print("new incl gathers", t(lambda: spans_t(aT[:, pair], bT[:, pair], cT[:, pair], rows, width)))
x = _row_spans(a[pair], b[pair], c[pair], rows, width); y = spans_t(aT[:, pair], bT[:, pair], cT[:, pair], rows, width)
print(torch.equal(x[0], y[0]), torch.equal(x[1], y[1]))
