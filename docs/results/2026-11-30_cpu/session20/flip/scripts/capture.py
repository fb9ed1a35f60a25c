# ruff: noqa: E402, E501, E701, E702
"""capture.py TREE SOURCES_CACHE OUT_DIR PROPOSALS: the arguments of the proposal fit (sdn3d.proposal_fit.fit_proposals
of THIS tree's code) of every PROPOSALS (semantic | gt) source scene that a Table 1 de-render cache (SOURCES_CACHE, its
*.pt scenes' meta["source"]) names, de-rendered with session 11's demo weights at 312x96 on the photo path, the fit
itself skipped: replay.py fits them again. The pattern of session 18 tierule's capture.py, without its template belief
(not on main)."""
import glob
import os
import sys

import torch

import sdn3d.derender as dr
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models

tree, sources_from, out, proposals = sys.argv[1:5]
os.makedirs(out, exist_ok=True)
sources = sorted({s.meta["source"] for s in (torch.load(f, weights_only=False) for f in glob.glob(sources_from + "/*.pt"))
                  if s.meta["proposals"] == proposals})
records = index_records(read_frames(tree))
R = "/tmp/s11data/demo/out/runs"
models = Models.from_checkpoints(f"{R}/semantic/checkpoints/inference.pt", f"{R}/geometric/checkpoints/inference.pt", None)
NAMES = ("intr", "masks", "ids", "rows", "geometry", "settings", "appearance", "unsure", "classes")
STATE = {}


def no_fit(*a):
    STATE.update(zip(NAMES, a, strict=True))
    return tuple(g.clone() for g in a[4]), []


dr.fit_proposals = no_fit
torch.set_num_threads(1)
for s in sources:
    _, w, var, fr = s.split("/")
    path = os.path.join(out, f"{w}_{var}_{fr}.pt")
    if os.path.exists(path): continue
    rec = records[(w, var, int(fr))]
    src = load_frame(rec, (312, 96), semantic=False, instances=False)
    STATE.clear()
    dr.derender(src.image, src.intrinsics, models, proposals, ground_truth(rec, (312, 96)), min_pixels=64,
                fit=FitSettings(), photo=frame_photo(rec, (312, 96)))
    if "rows" not in STATE: continue  # no vehicle to fit
    STATE.pop("settings")
    torch.save({"source": s, **STATE}, path + ".tmp")
    os.replace(path + ".tmp", path)
    print(s, len(STATE["rows"]), flush=True)
