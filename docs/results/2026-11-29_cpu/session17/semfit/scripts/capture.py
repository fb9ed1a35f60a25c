# ruff: noqa: E402, E501, E701, E702
"""capture.py TREE FRAMES_FROM_CACHE OUT_DIR: the arguments of the proposal fit (sdn3d.proposal_fit.fit_proposals) of
every semantic source scene of a Table 1 tree (the frames a de-render cache of run.sh names), de-rendered with the
demo weights at 312x96, the fit itself skipped: replay.py fits them again under a variant. Session 12 cutmask's
capture.py did the same with the fit run."""
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

tree, frames_from, out = sys.argv[1:4]
os.makedirs(out, exist_ok=True)
sources = sorted({s.meta["source"] for s in (torch.load(f, weights_only=False) for f in glob.glob(frames_from + "/*.pt"))
                  if s.meta["proposals"] == "semantic"})
records = index_records(read_frames(tree))
R = "/tmp/s11data/demo/out/runs"
models = Models.from_checkpoints(f"{R}/semantic/checkpoints/inference.pt", f"{R}/geometric/checkpoints/inference.pt", None)
STATE = {}


def no_fit(*a, **k):
    STATE["fit_args"] = a
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
    dr.derender(src.image, src.intrinsics, models, "semantic", ground_truth(rec, (312, 96)), min_pixels=64,
                fit=FitSettings(), photo=frame_photo(rec, (312, 96)))
    intr, masks, ids, rows, geometry, settings, appearance, unsure, classes = STATE["fit_args"]
    torch.save({"source": s, "intr": intr, "masks": masks, "ids": ids, "rows": rows, "geometry": geometry,
                "appearance": appearance, "unsure": unsure, "classes": classes}, path + ".tmp")
    os.replace(path + ".tmp", path)
    print(s, len(rows), flush=True)
