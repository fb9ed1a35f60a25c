# ruff: noqa: INP001, E501
"""nab.py REPEATS: nearest_examples of the code on PYTHONPATH on the captured part-lookup calls (cap_nearest.py),
REPEATS times over all of them, every answer checked against the captured one; prints the least CPU ms of a pass."""
import sys
import time

import torch

from sdn3d.editing.photo import nearest

torch.set_num_threads(1)
calls = torch.load("/tmp/s38photo/nearest_calls.pt")
best = float("inf")
for _ in range(int(sys.argv[1])):
    c0 = time.process_time()
    for query, examples, k, shared_from, want in calls:
        got = nearest.nearest_examples(query, examples, k, shared_from)
        assert torch.equal(got, want)
    best = min(best, 1000 * (time.process_time() - c0))
print(f"{best:.1f}")
