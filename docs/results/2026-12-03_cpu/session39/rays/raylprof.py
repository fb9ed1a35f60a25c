# ruff: noqa: INP001, E501
"""raylprof.py N CAP_DIR SPEC FUNC...: line timings (line_profiler, installed apart: pip install --target
/tmp/s39rays/lp line_profiler, put last on sys.path) of road.py's FUNC over N ray_fill calls of a captured spec."""
import pickle
import sys

sys.path.append("/tmp/s39rays/lp")
import torch  # noqa: E402
from line_profiler import LineProfiler  # noqa: E402

from sdn3d.editing.photo import road  # noqa: E402

torch.set_num_threads(1)
n, cap, spec, names = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4:]
lp = LineProfiler()
for name in names:
    setattr(road, name, lp(getattr(road, name)))
with open(f"{cap}/{spec}_0.pkl", "rb") as fh:
    rec = pickle.load(fh)
i = pickle.loads(rec["inputs"])
road.ray_fill(*i["args"], **i["kw"])  # warm: imports
lp = LineProfiler()
for name in names:
    setattr(road, name, lp(getattr(road, name).__wrapped__))
for _ in range(n):
    i = pickle.loads(rec["inputs"])
    road.ray_fill(*i["args"], **i["kw"])
lp.print_stats(output_unit=1e-3, stripzeros=True)
