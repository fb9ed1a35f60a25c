# ruff: noqa: INP001, E501
"""lprof2.py SPEC N FUNC...: line timings (line_profiler, installed apart: pip install --target /tmp/s38photo/lp) over N
photo stages of a captured spec (bench.py's inputs); FUNC as module.name, e.g. transfer._part_colors."""
import pickle
import sys

import torch
from line_profiler import LineProfiler

from sdn3d.editing.photo import fill, light, nearest, road, transfer

torch.set_num_threads(1)
spec, n, names = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
lp = LineProfiler()
mods = {"transfer": transfer, "road": road, "nearest": nearest, "fill": fill, "light": light}
for name in names:
    m, *path = name.split(".")
    owner = mods[m]
    for p in path[:-1]:
        owner = getattr(owner, p)
    setattr(owner, path[-1], lp(getattr(owner, path[-1])))
a = pickle.load(open(f"/tmp/s38photo/cap/{spec}.pkl", "rb"))
for _ in range(n):
    src = transfer.PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
    transfer.render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"], a["recolor"],
                          None, source=src)
lp.print_stats(output_unit=1e-3, stripzeros=True)
