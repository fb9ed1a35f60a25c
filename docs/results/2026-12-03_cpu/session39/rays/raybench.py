# ruff: noqa: INP001, E501
"""raybench.py N CAP_DIR SPEC...: ray_fill (the code on PYTHONPATH) N times on each captured call (capray.py); prints
the least and median CPU ms per call and whether the picture and the reached mask equal the captured base's, bit for
bit. With PROFILE=FILE, a cProfile (CPU time) of the N runs of all specs is written there and its top printed."""
import cProfile
import os
import pickle
import pstats
import statistics
import sys
import time

import torch

from sdn3d.editing.photo.road import ray_fill

torch.set_num_threads(1)
n, cap = int(sys.argv[1]), sys.argv[2]
prof = cProfile.Profile(time.process_time) if os.environ.get("PROFILE") else None
for spec in sys.argv[3:]:
    with open(f"{cap}/{spec}_0.pkl", "rb") as fh:
        rec = pickle.load(fh)
    cpu = []
    for _ in range(n):
        i = pickle.loads(rec["inputs"])  # fresh inputs (and PictureLab) each run
        c0 = time.process_time()
        if prof:
            prof.enable()
        out, reached = ray_fill(*i["args"], **i["kw"])
        if prof:
            prof.disable()
        cpu.append(1000 * (time.process_time() - c0))
    same = torch.equal(out, rec["out"][0]) and torch.equal(reached, rec["out"][1])
    print(f"{spec}: cpu min {min(cpu):.1f} median {statistics.median(cpu):.1f} ms  same={same}", flush=True)
if prof:
    prof.dump_stats(os.environ["PROFILE"])
    for key in ("tottime", "cumtime"):
        pstats.Stats(os.environ["PROFILE"]).strip_dirs().sort_stats(key).print_stats(35)
