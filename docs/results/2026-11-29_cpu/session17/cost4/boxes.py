"""boxes.png: what the photo path now rasterizes. For three of the 14 latency edits (session14/cost/draw_edits.py's
cases), the input picture (1242x375) with the box of the source rasterization (every object of the scene, yellow)
and of the edited objects' rasterization (blue), each labelled with its share of the picture: the z-buffer and the
fragments are these boxes', where main's were the whole picture's.

    python boxes.py TREE OUT.png
"""

import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.records import load_rgb
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.synth import BENCHMARK_NAME
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.apply import apply_edits, ops_from_benchmark
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo import transfer
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.evaluation.edit_benchmark import edit_kind

tree, out = Path(sys.argv[1]), Path(sys.argv[2])
torch.set_num_threads(1)
boxes = []
rasterize = transfer._rasterize


def record(*args):
    raster = rasterize(*args)
    boxes.append(raster.frags.box)
    return raster


transfer._rasterize = record
records = {(r.world, r.variation, int(r.frame)): r for r in read_frames(tree)}
entries = [e for e in load_edit_benchmark(tree / BENCHMARK_NAME) if e.operations][:40]
renderer = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
panels = []
for i in (1, 4, 10):
    entry = entries[i]
    record_ = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(record_, (624, 192))
    original = torch.from_numpy(np.ascontiguousarray(load_rgb(record_))).permute(2, 0, 1)
    edited = apply_edits(scene, ops_from_benchmark(entry, scene, (1242, 375), strict=False))
    frame = PixelFrame((1242, 375), (624, 192))
    boxes.clear()
    renderer.draw(renderer.prepare(original, frame, scene), edited)
    picture = Image.fromarray(original.permute(1, 2, 0).numpy())
    pen = ImageDraw.Draw(picture)
    label = f"edit {i} ({edit_kind(entry)}), 1242x375:"
    for (x0, y0, x1, y1), colour, what in zip(boxes, ((255, 220, 0), (40, 140, 255)), ("source", "edited"),
                                               strict=False):
        pen.rectangle((x0, y0, x1 - 1, y1 - 1), outline=colour, width=3)
        label += f"  {what} box {x1 - x0}x{y1 - y0} = {(x1 - x0) * (y1 - y0) / (1242 * 375):.1%}"
        pen.text((x0 + 4, y0 + 4 if colour[0] == 255 else y1 - 16), what, fill=colour)
    pen.rectangle((0, 0, 8 * len(label) // 1 + 10, 16), fill=(0, 0, 0))
    pen.text((5, 2), label, fill=(255, 255, 255))
    panels.append(np.asarray(picture))
Image.fromarray(np.concatenate(panels, 0)).save(out)
