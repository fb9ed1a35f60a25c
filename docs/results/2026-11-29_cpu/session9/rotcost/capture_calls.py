# ruff: noqa: E402, E501, E701, E702
"""capture.py: runs lat3's rotate edits and saves the arguments of _rasterize, dilate_square and torch.cdist calls."""
import pickle
import sys

sys.path.insert(0, "/work/wt/s9-rotcost/docs/results/2026-11-29_cpu/session9/rotcost")
import torch

torch.set_num_threads(1)
from prof import cases

import sdn3d.editing.photo.fill as fill
import sdn3d.editing.photo.road as road
import sdn3d.editing.photo.transfer as tr
import sdn3d.image_ops as io
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.photo.settings import PhotoSettings

rec = {"raster": [], "dilate": [], "cdist": []}
real_r = tr._rasterize
def r(*a):
    rec["raster"].append(a); return real_r(*a)
tr._rasterize = r
real_d = io.dilate_square
def d(m, rad):
    rec["dilate"].append((m.clone(), rad)); return real_d(m, rad)
for mod in (tr, road, fill, io):
    if hasattr(mod, "dilate_square"): mod.dilate_square = d
real_c = torch.cdist
def c(a, b, *k, **kw):
    rec["cdist"].append((a.clone(), b.clone())); return real_c(a, b, *k, **kw)
torch.cdist = c
cs, frame = cases("/tmp/s5data/deletes/lat3")
rr = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
for kind, scene, edited, original in cs:
    if kind != "rotate": continue
    rr.draw(rr.prepare(original, frame, scene), edited)
pickle.dump(rec, open("/tmp/s9data/rotcost/cap/rotate_calls.pkl", "wb"))
print({k: len(v) for k, v in rec.items()})
