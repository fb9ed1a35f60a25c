# ruff: noqa: INP001, E501
"""rayab.py ROUNDS CAP_DIR BASE_ROAD SPEC...: ray_fill of the base's road.py (BASE_ROAD, loaded apart as a module of
its own; its imports resolve to the code on PYTHONPATH, whose other modules are the base's) against the code on
PYTHONPATH, alternated within each round (the order flipped every other round), one thread, on captured calls
(capray.py). Each round runs each arm 3 times and keeps its least CPU time; every result is checked against the
captured base's, bit for bit. Prints per spec the medians and the paired new / base ratio (median, min, max)."""
import importlib.util
import pickle
import statistics
import sys
import time

import torch

from sdn3d.editing.photo import road as new

torch.set_num_threads(1)
rounds, cap, base_path, specs = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4:]
spec = importlib.util.spec_from_file_location("road_base", base_path)
base = importlib.util.module_from_spec(spec)
spec.loader.exec_module(base)
arms = {"base": base.ray_fill, "new": new.ray_fill}
recs = {}
for s in specs:
    with open(f"{cap}/{s}_0.pkl", "rb") as fh:
        recs[s] = pickle.load(fh)
    for f in arms.values():  # warm: imports, the kernel's load
        i = pickle.loads(recs[s]["inputs"])
        f(*i["args"], **i["kw"])
times = {(s, a): [] for s in specs for a in arms}
for r in range(rounds):
    for s in specs:
        rec = recs[s]
        for a in (("base", "new") if r % 2 == 0 else ("new", "base")):
            best = float("inf")
            for _ in range(3):
                i = pickle.loads(rec["inputs"])
                c0 = time.process_time()
                out, reached = arms[a](*i["args"], **i["kw"])
                best = min(best, 1000 * (time.process_time() - c0))
                assert torch.equal(out, rec["out"][0]) and torch.equal(reached, rec["out"][1]), (s, a)
            times[(s, a)].append(best)
print("| spec | base, median ms | new, median ms | new / base, paired median (min, max) |")
print("|---|---|---|---|")
for s in specs:
    b, n = times[(s, "base")], times[(s, "new")]
    ratio = [y / x for x, y in zip(b, n, strict=True)]
    print(f"| {s} | {statistics.median(b):.1f} | {statistics.median(n):.1f} | {statistics.median(ratio):.3f} ({min(ratio):.3f}, {max(ratio):.3f}) |", flush=True)
