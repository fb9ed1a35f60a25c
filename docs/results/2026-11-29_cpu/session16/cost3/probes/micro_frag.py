# ruff: noqa: E401, E402, E501, E701, E702, B023, F401, F841, I001
"""A probe of one cost this helper looked at and did not cut (README section 4); run from the worktree with
PYTHONPATH=src, threads 1."""
import time, torch
from sdn3d.render.rasterize import _empty_fragments
torch.set_num_threads(1)
def t(f, n=9):
    best = 1e9; ts = []
    for _ in range(n):
        t0 = time.perf_counter(); r = f(); ts.append(1000 * (time.perf_counter() - t0)); del r
    return [round(x, 2) for x in ts]
print("empty_fragments f64", t(lambda: _empty_fragments(1, 375, 1242, torch.float64, torch.device("cpu"))))
print("full long", t(lambda: torch.full((1, 375, 1242), -1, dtype=torch.long)))
print("zeros bary", t(lambda: torch.zeros(1, 375, 1242, 3, dtype=torch.float64)))
print("empty bary", t(lambda: torch.empty(1, 375, 1242, 3, dtype=torch.float64)))
keep = [torch.zeros(1, 375, 1242, 3, dtype=torch.float64) for _ in range(3)]
print("zeros bary while others held", t(lambda: torch.zeros(1, 375, 1242, 3, dtype=torch.float64)))
