"""Seconds per delete of render_photo at 1242x375, settings side by side in one process (the seed-31 tuning tree's
9 deletes, /work/notes/h9b/cf31, ground-truth scenes, a fresh PhotoSource per edit, one warm-up call per variant,
then the variants interleaved per delete so the machine's load hits them alike).

usage: delete_cost.py NAME:key=val,... [NAME:...]   (PhotoSettings keys; 'rays:' = the defaults)
"""

import statistics
import sys
import time
from pathlib import Path

import torch
import yaml

from sdn3d.data.counterfactual import load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import PhotoSource, render_photo

torch.set_num_threads(1)
root = Path("/work/notes/h9b/cf31")
index = load_pairs(root)
size = index.image_size
records = {(r.world, r.variation, r.frame): r for r in read_frames(root)}
deletes = [p for p in index.pairs if p.kind == "delete"]
frame = PixelFrame(size, size)
variants = {}
for arg in sys.argv[1:]:
    name, _, kv = arg.partition(":")
    variants[name] = PhotoSettings(**{k: yaml.safe_load(v) for k, v in (a.split("=", 1) for a in kv.split(",") if a)})
cases = []
for p in deletes:
    rec = records[(p.world, p.variation, p.frame)]
    image = load_frame(rec, size, semantic=False, instances=False).image
    scene = scene_from_frame(rec, size)
    cases.append((image, scene, apply_edits(scene, [Delete(p.instance_id)])))


def draw(settings, case):
    image, scene, edited = case
    t = time.perf_counter()
    render_photo(image, frame, scene, edited, settings=settings,
                 source=PhotoSource(image, frame, scene, settings=settings, max_fills=0))
    return time.perf_counter() - t


for settings in variants.values():
    draw(settings, cases[0])  # warm-up
times = {name: [] for name in variants}
for case in cases:
    for name, settings in variants.items():
        times[name].append(draw(settings, case))
print(f"{len(cases)} deletes at {size[0]}x{size[1]}, 1 thread, whole render_photo incl. PhotoSource")
print("| variant | median s | mean s | max s |\n|---|---|---|---|")
for name, t in times.items():
    print(f"| {name} | {statistics.median(t):.3f} | {statistics.mean(t):.3f} | {max(t):.3f} |")
