# ruff: noqa: E401, E402, E501, E701, E702, E731, I001, F401
import cProfile, pstats, sys, io, time
sys.path.insert(0, "docs/results/2026-11-29_cpu/session9/rot05")
import torch
torch.set_num_threads(1)
from prof import cases
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.photo.settings import PhotoSettings
cs, frame = cases("/tmp/s5data/deletes/lat3")
r = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
r.draw(r.prepare(cs[0][3], frame, cs[0][1]), cs[0][2])
pr = cProfile.Profile()
for kind, scene, edited, original in cs:
    if kind != sys.argv[1]: continue
    pr.enable(); r.draw(r.prepare(original, frame, scene), edited); pr.disable()
st = pstats.Stats(pr)
st.sort_stats("tottime").print_callers(r"built-in method torch.exp|quantile|'any'|torch.where|'sum' of|grid_sampler|stack")
