# ruff: noqa: E501, E701, E702
"""probe.py TREE WORLD/VARIATION/FRAME ID: the geometric branch's appearance reading (lamps, headlights, bins' ray) of one
ground-truth-mask (oracle) object of a frame, as the de-render hands it to the fit (the code on the path): why a fit's end changed."""
import sys

import torch

import sdn3d.derender as dr
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models

tree, key, iid = sys.argv[1], sys.argv[2], int(sys.argv[3])
records = index_records(read_frames(tree)); w, var, fr = key.split("/")
R = "/tmp/s11data/demo/out/runs"
models = Models.from_checkpoints(f"{R}/semantic/checkpoints/inference.pt", f"{R}/geometric/checkpoints/inference.pt", None)
S = {}
def no_fit(*a):
    S["a"] = a; return tuple(g.clone() for g in a[4]), []
dr.fit_proposals = no_fit
torch.set_num_threads(1)
rec = records[(w, var, int(fr))]; src = load_frame(rec, (312, 96), semantic=False, instances=False)
dr.derender(src.image, src.intrinsics, models, "gt", ground_truth(rec, (312, 96)), min_pixels=64, fit=FitSettings(), photo=frame_photo(rec, (312, 96)))
ids, app = S["a"][2], S["a"][6]
r = int((ids == iid).nonzero()[0])
print({k: (round(float(v[r]), 3) if v.dtype.is_floating_point else bool(v[r])) for k, v in app.values.items() if v.dim() == 1})
