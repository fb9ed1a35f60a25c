# ruff: noqa: INP001, E501
"""cprof2.py SPEC N OUT: cProfile (CPU time) over N photo stages of a captured spec; prints the top by tottime and cumtime."""
import cProfile
import pickle
import pstats
import sys
import time

import torch

from sdn3d.editing.photo import transfer

torch.set_num_threads(1)
spec, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
a = pickle.load(open(f"/tmp/s38photo/cap/{spec}.pkl", "rb"))
src = transfer.PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
transfer.render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"], a["recolor"],
                      None, source=src)  # warm: the kernel's load, lru caches
prof = cProfile.Profile(time.process_time)  # CPU time: less swayed by the shared machine's load
prof.enable()
for _ in range(n):
    src = transfer.PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
    transfer.render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"],
                          a["recolor"], None, source=src)
prof.disable()
prof.dump_stats(out)
for key in ("tottime", "cumtime"):
    pstats.Stats(out).strip_dirs().sort_stats(key).print_stats(30)
