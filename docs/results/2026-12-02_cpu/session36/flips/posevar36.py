# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""posevar36.py ARGS...: benchmarks/pose_table.py with the geometric branch's LampCue fields set from LAMPCUE
(e.g. LAMPCUE='white_open=2'), each value cast to its field's type; no LAMPCUE: as it is."""
import os, sys
from dataclasses import replace, fields as dc_fields
sys.path.insert(0, "/tmp/s36_flips/benchmarks")
import sdn3d.models as M
from sdn3d.geometric.lamps import LampCue
import pose_table
given = dict(kv.split("=") for kv in os.environ.get("LAMPCUE", "").split(",") if kv)
kinds = {f.name: type(f.default) for f in dc_fields(LampCue)}
if given:
    _fc = M.Models.from_checkpoints.__func__
    def fc(cls, *a, **k):
        m = _fc(cls, *a, **k)
        m.geometric.lamp_cue = replace(m.geometric.lamp_cue, **{n: kinds[n](v) for n, v in given.items()})
        print("lamp cue:", m.geometric.lamp_cue, file=sys.stderr)
        return m
    M.Models.from_checkpoints = classmethod(fc)
pose_table.main(sys.argv[1:])
