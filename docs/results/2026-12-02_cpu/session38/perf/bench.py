# ruff: noqa: INP001, E501
"""bench.py N SPEC...: render_photo (with a fresh PhotoSource, as sdn3d-edit's photo stage) N times per captured
spec; prints each spec's min / median wall ms, the first run's, the least CPU ms of the process (user and system: less
swayed by others' load on a shared machine than wall time) and a hash of the picture."""
import hashlib
import pickle
import statistics
import sys
import time

import torch

from sdn3d.editing.photo.transfer import PhotoSource, render_photo

torch.set_num_threads(1)
n = int(sys.argv[1])
for spec in sys.argv[2:]:
    with open(f"/tmp/s38photo/cap/{spec}.pkl", "rb") as fh:
        a = pickle.load(fh)
    times, cpu = [], []
    for _ in range(n):
        t0, c0 = time.perf_counter(), time.process_time()
        src = PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
        res = render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"], a["recolor"],
                           None, source=src)
        times.append(1000 * (time.perf_counter() - t0))
        cpu.append(1000 * (time.process_time() - c0))
    h = hashlib.sha1(res.image.numpy().tobytes()).hexdigest()[:12]
    print(f"{spec}: min {min(times):.0f} median {statistics.median(times):.0f} ms (first {times[0]:.0f}) cpu {min(cpu):.0f}  {h}", flush=True)
