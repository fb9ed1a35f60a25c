"""Per-delete cost of render_photo at 1242x375 (the seed-31 tuning tree's 9 deletes, ground-truth scenes, one
warm-up call, then all 9 profiled): python delete_cost.py rays|auto.
Prints seconds per edit and the 22 heaviest calls."""

import cProfile
import pstats
import sys
import time
from pathlib import Path

import torch

from sdn3d.data.counterfactual import load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import render_photo

torch.set_num_threads(1)
root = Path("/work/notes/h9b/cf31")
idx = load_pairs(root)
size = idx.image_size
recs = {(r.world, r.variation, r.frame): r for r in read_frames(root)}
dels = [p for p in idx.pairs if p.kind == "delete"]
frame = PixelFrame(size, size)
st = PhotoSettings(fill=sys.argv[1])
cases = []
for p in dels:
    rec = recs[(p.world, p.variation, p.frame)]
    image = load_frame(rec, size, semantic=False, instances=False).image
    scene = scene_from_frame(rec, size)
    cases.append((image, scene, apply_edits(scene, [Delete(p.instance_id)])))
render_photo(cases[0][0], frame, cases[0][1], cases[0][2], settings=st)
pr = cProfile.Profile()
t = time.perf_counter()
pr.enable()
for image, scene, ed in cases:
    render_photo(image, frame, scene, ed, settings=st)
pr.disable()
print("per edit s", (time.perf_counter() - t) / len(cases))
pstats.Stats(pr).sort_stats("cumulative").print_stats(22)
