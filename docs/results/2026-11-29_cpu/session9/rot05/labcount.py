# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import sys, collections, traceback, torch
torch.set_num_threads(1)
sys.path.insert(0, "/work/wt/s9-rot05/docs/results/2026-11-29_cpu/session9/rot05")
from prof import cases
import sdn3d.editing.photo.recolor as rc
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.photo.settings import PhotoSettings
cnt = collections.Counter(); calls = collections.Counter()
real = rc.srgb_to_lab
def spy(rgb):
    st = traceback.extract_stack(limit=4)
    key = " < ".join(f"{f.name}:{f.lineno}" for f in st[-3:-1][::-1])
    cnt[key] += len(rgb); calls[key] += 1
    return real(rgb)
rc.srgb_to_lab = spy
import sdn3d.editing.photo.transfer as tr
tr.srgb_to_lab = spy
cs, frame = cases("/tmp/s5data/deletes/lat3")
r = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
n = 0
for kind, scene, edited, original in cs:
    if kind == "rotate":
        r.draw(r.prepare(original, frame, scene), edited); n += 1
for k, v in cnt.most_common(): print(f"{v/n/1000:8.1f} kpx/edit {calls[k]/n:5.1f} calls/edit  {k}")
