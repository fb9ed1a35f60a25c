# ruff: noqa: INP001, E501
"""faults.py SPEC [again]: one sdn3d-edit run whose photo stage prints its page faults, wall ms and user and system
CPU ms (again: then twice more in the same process, the source state made anew)."""
import resource
import sys
import time

from sdn3d.cli import edit
from sdn3d.editing import appearance

draw = appearance.PhotoRenderer.draw


def timed(self, *args, **kwargs):
    runs = 3 if len(sys.argv) > 2 else 1
    for run in range(runs):
        if run:
            args[0].photo = None  # the source state made anew
        u0, t0 = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
        out = draw(self, *args, **kwargs)
        u1 = resource.getrusage(resource.RUSAGE_SELF)
        print(f"faults {u1.ru_minflt - u0.ru_minflt} ms {1000 * (time.perf_counter() - t0):.0f} user "
              f"{1000 * (u1.ru_utime - u0.ru_utime):.0f} sys {1000 * (u1.ru_stime - u0.ru_stime):.0f}", file=sys.stderr)
    return out


appearance.PhotoRenderer.draw = timed
edit.main(["input.image=tests/data/0006_30-deg-right_00043.png",
           f"edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/{sys.argv[1]}.yaml",
           "run=/tmp/w38/outputs/demo/runs", "proposals=boxes", "threads=1", "output_dir=/tmp/s38photo/f",
           "overwrite=true", "progress=false"])
