# ruff: noqa: E402, E501, E701, E702
"""gtcheck.py TREE MAIN_CACHE N: the ground-truth-mask (oracle) de-renders of the first N source frames that MAIN_CACHE
(run.sh's cache of main's gt row) holds, made again with the code on PYTHONPATH (the benchmark's derender call: demo
weights, 312x96, min_pixels 64, the default FitSettings), compared with main's cached scenes: every object's template,
dims, yaw, location, FFD and mask, and the fits' records. Prints the frames that differ and a count."""
import glob
import sys

import torch

from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import derender
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models

tree, cache, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
records = index_records(read_frames(tree))
R = "/tmp/s11data/demo/out/runs"
models = Models.from_checkpoints(None, f"{R}/geometric/checkpoints/inference.pt", f"{R}/textural/checkpoints/inference.pt")
torch.set_num_threads(1)
scenes = sorted((s for s in (torch.load(f, weights_only=False) for f in glob.glob(cache + "/*.pt")) if s.meta["proposals"] == "gt"), key=lambda s: s.meta["source"])[:n]
same = 0
for old in scenes:
    _, w, var, fr = old.meta["source"].split("/")
    rec = records[(w, var, int(fr))]
    src = load_frame(rec, (312, 96), semantic=False, instances=False)
    new = derender(src.image, src.intrinsics, models, "gt", ground_truth(rec, (312, 96)), min_pixels=64, fit=FitSettings(), photo=frame_photo(rec, (312, 96)))
    a, b = old.objects, new.objects
    ok = all(torch.equal(getattr(a, k), getattr(b, k)) for k in ("instance_id", "template_id", "dims", "ry", "location", "phi", "mask")) and old.meta["fits"] == new.meta["fits"]
    same += ok
    if not ok: print("differs:", old.meta["source"], flush=True)
print(f"{tree}: {same} of {len(scenes)} ground-truth-mask de-renders identical to main's")
