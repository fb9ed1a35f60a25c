# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""airprobe.py TREE W OUT: cutcars.py's run with each white_lamps reading's air (air_offset) recorded per object."""
import sys, json, runpy, torch
import sdn3d.geometric.lamps as L
rec = []
_wl = L.white_lamps
def wl(crop, mask, cue=None):
    out = _wl(crop, mask, cue)
    c = cue or L.LampCue()
    m = (mask[:, 0] if mask.dim() == 4 else mask) > 0.5
    air, t = L.air_offset(crop, m, c.clear_dark)
    rec.append({"air": air.mean(1).tolist(), "t": t.tolist(), "present": out[0].tolist(), "usable": out[1].tolist()})
    return out
L.white_lamps = wl
sys.argv = ["cutcars.py", sys.argv[1], sys.argv[2], sys.argv[3] + ".cut.json", "312", "96"]
try:
    runpy.run_path("/work/notes/s34/flips/cutcars.py", run_name="__main__")
finally:
    json.dump(rec, open(sys.argv[3].replace(".cut.json", "") , "w"))
