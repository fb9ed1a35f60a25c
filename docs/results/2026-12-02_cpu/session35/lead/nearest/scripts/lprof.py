# ruff: noqa: B007, E401, E402, E501, E701, E702, F401, F541, I001
import os, sys
from line_profiler import LineProfiler
import sdn3d.editing.photo.transfer as T
from sdn3d.cli.edit import main
lp = LineProfiler(T._corner_part_colors, T._part_colors, T._corner_groups, T._members)
orig = T._corner_part_colors
def wrapped(*a, **k):
    lp.enable_by_count()
    try: return orig(*a, **k)
    finally: lp.disable_by_count()
T._corner_part_colors = wrapped
try:
    main(["input.image=tests/data/0006_30-deg-right_00043.png", f"edits=/work/notes/s35/photo/{os.environ.get('SPEC','t1')}.yaml",
          "run=/tmp/w35/outputs/demo/runs", "proposals=boxes", "threads=1", "output_dir=/tmp/s35_prof2", "overwrite=true", "progress=false"])
except SystemExit:
    pass
lp.print_stats(output_unit=1e-3, stripzeros=True)
