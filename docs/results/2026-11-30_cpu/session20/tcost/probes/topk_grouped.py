# ruff: noqa: E402
"""A selection of the k nearest examples tried and not kept: torch's ``topk`` of the ``(Q, E)`` float32 distances
``_nearest_examples`` computes, against the k least values found among the columns of the k groups (of 16 columns
each) with the least minima, checked to be topk's answer wherever the k + 1 least candidates are strictly increasing
and the k-th is below every other group's minimum (else topk of that row): the same indices, here on the calls of
session 14's draw_edits.py (its arguments follow), and the least of 5 wall times of each, alternating.

    python topk_grouped.py TREE OUT [draw_edits args...]
"""

import math
import runpy
import sys
import time

import torch

import sdn3d.editing.photo.transfer as transfer

DRAW_EDITS = "docs/results/2026-11-29_cpu/session14/cost/draw_edits.py"


def k_least_grouped(d: torch.Tensor, k: int, per: int = 16) -> torch.Tensor:
    q, e = d.shape
    groups = -(-e // per)
    if groups <= k + 1 or not q:
        return d.topk(k, largest=False).indices
    minima = d[:, :groups].clone()  # group g: columns g, g + G, g + 2G, ...
    for s in range(1, per):
        lo, hi = s * groups, min((s + 1) * groups, e)
        if lo >= e:
            break
        torch.minimum(minima[:, :hi - lo], d[:, lo:hi], out=minima[:, :hi - lo])
    if bool(torch.isnan(minima).any()):
        return d.topk(k, largest=False).indices
    g_val, g_idx = minima.topk(k + 1, largest=False)
    cols = (g_idx[:, :k, None] + groups * torch.arange(per)).flatten(1)
    cand = torch.where(cols < e, d.gather(1, cols.clamp(max=e - 1)), math.inf)
    c_val, c_idx = cand.topk(k + 1, largest=False)
    ok = (c_val[:, 1:] > c_val[:, :-1]).all(1) & (c_val[:, k - 1] < g_val[:, k])
    out = cols.gather(1, c_idx[:, :k])
    if not bool(ok.all()):
        bad = (~ok).nonzero().flatten()
        out[bad] = d[bad].topk(k, largest=False).indices
    return out


calls = []
nearest = transfer._nearest_examples


def recorded(query, examples, k):
    calls.append((query.clone(), examples.clone(), k))
    return nearest(query, examples, k)


transfer._nearest_examples = recorded
sys.argv = [DRAW_EDITS, *sys.argv[1:]]
runpy.run_path(DRAW_EDITS, run_name="__main__")
cdist_s = topk_s = grouped_s = 0.0
for query, examples, k in calls:
    k = min(k, len(examples))
    d = torch.cdist(query.float(), examples.float())
    assert torch.equal(d.topk(k, largest=False).indices, k_least_grouped(d, k))
    best = [float("inf")] * 3
    for _ in range(5):
        t0 = time.perf_counter()
        torch.cdist(query.float(), examples.float())
        t1 = time.perf_counter()
        d.topk(k, largest=False)
        t2 = time.perf_counter()
        k_least_grouped(d, k)
        t3 = time.perf_counter()
        best = [min(b, x) for b, x in zip(best, (t1 - t0, t2 - t1, t3 - t2), strict=True)]
    cdist_s, topk_s, grouped_s = cdist_s + best[0], topk_s + best[1], grouped_s + best[2]
print(f"{len(calls)} calls, the same indices; cdist {1000 * cdist_s:.1f} ms, topk {1000 * topk_s:.1f} ms, grouped "
      f"selection {1000 * grouped_s:.1f} ms (sums of the least of 5)")
