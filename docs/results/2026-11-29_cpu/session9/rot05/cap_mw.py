# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import sys, pickle, torch
torch.set_num_threads(1)
sys.path.insert(0, "/work/wt/s9-rot05/docs/results/2026-11-29_cpu/session9/rot05")
from prof import cases
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.photo.settings import PhotoSettings
import sdn3d.editing.photo.road as road
rec = []
orig = road._matched_weight
def cap(*a, **k):
    rec.append((a, k)); return orig(*a, **k)
road._matched_weight = cap
cs, frame = cases("/tmp/s5data/deletes/lat3")
r = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
for kind, scene, edited, original in cs:
    if kind == "rotate":
        r.draw(r.prepare(original, frame, scene), edited)
pickle.dump(rec, open("/tmp/s9data/rot05/mw_calls.pkl", "wb"))
print(len(rec))
