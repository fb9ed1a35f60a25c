# ruff: noqa: INP001, E501
"""cold.py SPEC OUT: cProfile of the first photo stage in a fresh process (as sdn3d-edit's, which runs it once) on a
captured spec, then of a second, warm one; prints each's top by tottime."""
import cProfile
import pickle
import pstats
import sys

import torch

from sdn3d.editing.photo import transfer

torch.set_num_threads(1)
spec, out = sys.argv[1], sys.argv[2]
a = pickle.load(open(f"/tmp/s38photo/cap/{spec}.pkl", "rb"))
for name in ("cold", "warm"):
    prof = cProfile.Profile()
    prof.enable()
    src = transfer.PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
    transfer.render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"],
                          a["recolor"], None, source=src)
    prof.disable()
    prof.dump_stats(f"{out}.{name}")
    print(f"==== {name}")
    pstats.Stats(f"{out}.{name}").strip_dirs().sort_stats("tottime").print_stats(25)
