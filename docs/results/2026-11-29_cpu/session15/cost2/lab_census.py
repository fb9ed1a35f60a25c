# ruff: noqa: E402
"""The road tests' Lab conversions of the 14 latency edits (session14/cost/draw_edits.py, run in this process) with
the code on PYTHONPATH: pixels converted and CPU ms per edit, by caller. Main converts in road_lab (every caller);
this branch converts the source picture's pixels in PictureLab._convert and what is no picture pixel (the fill's
own colours, ray samples) in road_lab.

    PYTHONPATH=CODE/src python lab_census.py TREE OUT_PREFIX
"""

import collections
import inspect
import runpy
import sys
import time
from pathlib import Path

import sdn3d.editing.photo.road as road

pixels: collections.Counter = collections.Counter()
cpu: collections.Counter = collections.Counter()
calls: collections.Counter = collections.Counter()
depth = [0]


def counted(fn, name_of):
    def wrapper(*args, **kwargs):
        if depth[0]:
            return fn(*args, **kwargs)
        name, n = name_of(*args, **kwargs)
        depth[0] += 1
        t = time.process_time()
        try:
            return fn(*args, **kwargs)
        finally:
            depth[0] -= 1
            cpu[name] += time.process_time() - t
            pixels[name] += n
            calls[name] += 1
    return wrapper


def road_lab_name(rgb):
    return f"road_lab <- {inspect.stack()[2].function}", len(rgb)


def convert_name(self, y0, x0, need, h=0, w=0):
    import numpy as np

    todo = ~self._done[y0:y0 + (need.shape[0] if need is not None else h), x0:x0 + (need.shape[1] if need is not None
                                                                                      else w)]
    if need is not None:
        todo = todo & need
    return f"PictureLab <- {inspect.stack()[3].function}", int(np.count_nonzero(todo))


road.road_lab = counted(road.road_lab, road_lab_name)
if hasattr(road, "PictureLab"):
    road.PictureLab._convert = counted(road.PictureLab._convert, convert_name)
here = Path(__file__).resolve().parent
draw = here.parents[1] / "session14" / "cost" / "draw_edits.py"
sys.argv = [str(draw), sys.argv[1], sys.argv[2]]
runpy.run_path(str(draw), run_name="__main__")
edits = 14
print(f"per edit (mean of {edits}): calls, thousand pixels converted, CPU ms")
for name in sorted(pixels):
    print(f"  {name}: {calls[name] / edits:.1f} calls, {pixels[name] / edits / 1000:.1f} k px, "
          f"{1000 * cpu[name] / edits:.1f} ms")
print(f"  all: {sum(pixels.values()) / edits / 1000:.1f} k px, {1000 * sum(cpu.values()) / edits:.1f} ms")
