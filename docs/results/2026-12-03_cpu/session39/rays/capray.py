# ruff: noqa: INP001, E501
"""capray.py SPEC OUT_DIR: run sdn3d-edit on one of session 35's real-frame specs and pickle every ray_fill call's
arguments and result (OUT_DIR/SPEC_K.pkl, K the call's index), for rayab.py to time and check."""
import pickle
import sys

from sdn3d.cli import edit
from sdn3d.editing.photo import road

spec, out = sys.argv[1], sys.argv[2]
orig = road.ray_fill
calls = []


def ray_fill(*args, **kw):
    before = pickle.dumps({"args": args, "kw": kw})  # before the call: its PictureLab as the call finds it
    res = orig(*args, **kw)
    with open(f"{out}/{spec}_{len(calls)}.pkl", "wb") as fh:
        pickle.dump({"inputs": before, "out": res}, fh)
    calls.append(1)
    return res


road.ray_fill = ray_fill
edit.main([
    "input.image=tests/data/0006_30-deg-right_00043.png",
    f"edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/{spec}.yaml",
    "run=/tmp/w39/outputs/demo/runs", "proposals=boxes", "threads=1", f"output_dir=/tmp/s39rays/capout/{spec}",
    "overwrite=true", "progress=false"])
print(spec, len(calls), "calls")
