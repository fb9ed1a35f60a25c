# ruff: noqa: E402
"""``_sample`` of the code on PYTHONPATH against sampling every pyramid level (the test's ``_sample_every_level``,
main's formulation) on the calls the photo path makes during session 14's draw_edits.py (its arguments follow): the
outputs equal, and the least of 5 wall times of each, alternating, summed over the calls.

    python sample_levels.py TREE OUT [draw_edits args...]
"""

import runpy
import sys
import time

import torch

import sdn3d.editing.photo.transfer as transfer
from tests.test_photo_cost import _sample_every_level

DRAW_EDITS = "docs/results/2026-11-29_cpu/session14/cost/draw_edits.py"
calls = []
sample = transfer._sample


def recorded(pyramid, uv, level):
    calls.append((pyramid, uv.clone(), level.clone()))
    return sample(pyramid, uv, level)


transfer._sample = recorded
sys.argv = [DRAW_EDITS, *sys.argv[1:]]
runpy.run_path(DRAW_EDITS, run_name="__main__")
new = old = 0.0
for pyramid, uv, level in calls:
    best_new = best_old = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        got = sample(pyramid, uv, level)
        t1 = time.perf_counter()
        want = _sample_every_level(pyramid, uv, level)
        t2 = time.perf_counter()
        best_new, best_old = min(best_new, t1 - t0), min(best_old, t2 - t1)
    assert torch.equal(got, want)
    new, old = new + best_new, old + best_old
shapes = [(len(uv), len(p), float(level.max()) if len(uv) else 0.0) for p, uv, level in calls[:12]]
print(f"{len(calls)} calls, all equal; this code {1000 * new:.1f} ms, every level {1000 * old:.1f} ms (sums of the "
      f"least of 5); (points, pyramid levels, the largest level asked) of the first 12: {shapes}")
