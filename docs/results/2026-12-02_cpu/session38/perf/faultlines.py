# ruff: noqa: INP001, E501
"""faultlines.py SPEC [RUNS]: the page faults (first touches of fresh memory) of the photo stage on a captured spec,
attributed to the line of sdn3d's photo code that took them (a line tracer reads the process's count at each line
of those files; a line's own faults, those of the photo lines it calls left out); the first run (a fresh process's, as sdn3d-edit's)
or the last of RUNS; prints the top 40 lines."""
import collections
import pickle
import resource
import sys

import torch

from sdn3d.editing.photo import transfer

torch.set_num_threads(1)
spec, runs = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 1
a = pickle.load(open(f"/tmp/s38photo/cap/{spec}.pkl", "rb"))
faults: collections.Counter = collections.Counter()
state: list = [None, 0]  # the innermost photo line being run, and the count when it began


def tracer(frame, event, arg):
    if "sdn3d/editing/photo" not in frame.f_code.co_filename:
        return None
    now = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    if state[0] is not None:
        faults[state[0]] += now - state[1]
    name = frame.f_code.co_filename.rsplit("/", 1)[-1]
    if event == "return":
        caller = frame.f_back
        inside = caller is not None and "sdn3d/editing/photo" in caller.f_code.co_filename
        state[0] = (caller.f_code.co_filename.rsplit("/", 1)[-1], caller.f_lineno) if inside else None
    else:
        state[0] = (name, frame.f_lineno)
    state[1] = now
    return tracer


for _ in range(runs):
    faults.clear()
    f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    sys.settrace(tracer)
    src = transfer.PhotoSource(a["original"], a["frame"], a["scene"], a["bank"], a["settings"])
    transfer.render_photo(a["original"], a["frame"], a["scene"], a["edited"], a["bank"], a["settings"], a["recolor"],
                          None, source=src)
    sys.settrace(None)
    total = resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0
print(f"{spec}: {total} faults in the photo stage (run {runs}); by line:")
for (name, line), n in faults.most_common(40):
    print(f"{n:7d}  {name}:{line}")
