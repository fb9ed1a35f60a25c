# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""posevar.py ARGS...: benchmarks/pose_table.py with the geometric branch's LampCue fields set from LAMPCUE (e.g.
LAMPCUE='lamp_top=0.3'); no LAMPCUE: as it is."""
import os, sys
from dataclasses import replace
sys.path.insert(0, "/work/main/benchmarks")
import sdn3d.models as M
import pose_table
fields = dict(kv.split("=") for kv in os.environ.get("LAMPCUE", "").split(",") if kv)
if fields:
    _fc = M.Models.from_checkpoints.__func__
    def fc(cls, *a, **k):
        m = _fc(cls, *a, **k)
        m.geometric.lamp_cue = replace(m.geometric.lamp_cue, **{k2: float(v) for k2, v in fields.items()})
        return m
    M.Models.from_checkpoints = classmethod(fc)
pose_table.main(sys.argv[1:])
