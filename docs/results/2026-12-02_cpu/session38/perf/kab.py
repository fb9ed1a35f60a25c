# ruff: noqa: INP001, E501
"""kab.py BASE_CPP NEW_CPP ROUNDS: the nearest-example kernel built from two sources of the same ABI, timed (CPU
time) on the captured calls (cap_nearest.py) through nearest_examples, alternated within each round (the order
flipped every other round); every answer checked against the captured one."""

import ctypes
import statistics
import sys
import time
from pathlib import Path

import torch

from sdn3d import native
from sdn3d.editing.photo import nearest

torch.set_num_threads(1)
calls = torch.load("/tmp/s38photo/nearest_calls.pt")
libs = {name: nearest._bind(ctypes.CDLL(str(native.build_kernel(native.compiler(), Path(path)))))
        for name, path in (("base", sys.argv[1]), ("new", sys.argv[2]))}


def run(lib: ctypes.CDLL) -> float:
    nearest.nearest_kernel = lambda: lib
    total = 0.0
    for query, examples, k, shared_from, want in calls:
        t0 = time.process_time()
        got = nearest.nearest_examples(query, examples, k, shared_from)
        total += time.process_time() - t0
        assert torch.equal(got, want)
    return 1000 * total


res: dict[str, list[float]] = {"base": [], "new": []}
for r in range(int(sys.argv[3])):
    for name in ("base", "new") if r % 2 == 0 else ("new", "base"):
        res[name].append(run(libs[name]))
ratio = [n / b for n, b in zip(res["new"], res["base"], strict=True)]
print(f"base median {statistics.median(res['base']):.1f} ms, new median {statistics.median(res['new']):.1f} ms, "
      f"ratio median {statistics.median(ratio):.3f} ({min(ratio):.3f}, {max(ratio):.3f})")
