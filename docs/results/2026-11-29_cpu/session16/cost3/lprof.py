"""Line profiles of named functions while a script runs (session 14's line_profiler install under
/tmp/s14data/cost/pylib, not in the venv):

    python lprof.py OUT.txt MODULE:QUALNAME[,MODULE:QUALNAME...] SCRIPT [SCRIPT ARGS...]

e.g. ``lprof.py lp.txt sdn3d.editing.photo.road:_trace session14/cost/draw_edits.py TREE OUT``; times in ms.
"""

import importlib
import runpy
import sys

sys.path.insert(0, "/tmp/s14data/cost/pylib")
from line_profiler import LineProfiler  # noqa: E402

out, names = sys.argv[1], sys.argv[2].split(",")
profiler = LineProfiler()
for name in names:
    module, qualname = name.split(":")
    obj = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    profiler.add_function(obj)
sys.argv = sys.argv[3:]
profiler.enable_by_count()
runpy.run_path(sys.argv[0], run_name="__main__")
profiler.disable_by_count()
with open(out, "w") as fh:
    profiler.print_stats(stream=fh, output_unit=1e-3)
