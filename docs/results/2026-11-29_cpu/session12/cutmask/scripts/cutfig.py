# ruff: noqa: E501, E702
"""cutfig.py TREE CAPTURE_DIR OUT.png WORLD/VAR/FRAME/ROW...: per semantic proposal (capture.py), three panels
enlarged 8x: the working image; the proposal's mask (red) with its ground-truth car's outline (green, oracle); the
semantic branch's class map (Road grey, GuardRail teal, Car red, others dark), each titled."""
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.labels import VKITTI_CLASS_INDEX

tree, cap, out = sys.argv[1:4]
records = index_records(read_frames(tree))
COLOURS = {"Road": (150, 150, 150), "GuardRail": (40, 160, 160), "Car": (220, 50, 50), "Truck": (230, 150, 40), "Van": (200, 80, 200)}
tiles = []
for spec in sys.argv[4:]:
    w, var, fr, r = spec.split("/"); r = int(r)
    c = torch.load(f"{cap}/{w}_{var}_{fr}.pt", weights_only=False)
    rec = records[(w, var, int(fr))]
    gm = scene_from_frame(rec, (312, 96)).objects.mask
    m = c["masks"][r]; g = int(((gm & m).flatten(1).sum(1)).argmax()); t = gm[g].numpy()
    img = np.asarray(Image.open(rec.rgb_path).convert("RGB").resize((312, 96), Image.BILINEAR)).copy()
    ys, xs = np.nonzero(t | m.numpy()); y0, y1, x0, x1 = max(ys.min() - 6, 0), min(ys.max() + 7, 96), max(xs.min() - 8, 0), min(xs.max() + 9, 312)
    crop = img[y0:y1, x0:x1]
    b = crop.copy(); b[m.numpy()[y0:y1, x0:x1]] = [255, 60, 60]
    e = t[y0:y1, x0:x1]; p = np.pad(e, 1)
    b[e & ~(p[2:, 1:-1] & p[:-2, 1:-1] & p[1:-1, 2:] & p[1:-1, :-2])] = [60, 255, 60]
    sem = c["semantic"].numpy()[y0:y1, x0:x1]
    s = np.full(sem.shape + (3,), 40, np.uint8)
    for name, col in COLOURS.items():
        s[sem == VKITTI_CLASS_INDEX[name]] = col
    cut = int(np.nonzero(t.any(1))[0].max() - np.nonzero(m.numpy().any(1))[0].max())
    titles = (f"{w}/{var} {fr}, proposal {r}", f"mask red, car green; cut {cut} px", "semantic: road grey, rail teal, car red")
    panels = [Image.fromarray(a).resize(((x1 - x0) * 8, (y1 - y0) * 8), Image.NEAREST) for a in (crop, b, s)]
    row = Image.new("RGB", (sum(q.width for q in panels) + 8, panels[0].height + 14), "white")
    x = 0
    for q, title in zip(panels, titles, strict=True):
        row.paste(q, (x, 14)); ImageDraw.Draw(row).text((x + 2, 1), title, fill="black"); x += q.width + 4
    tiles.append(row)
H = sum(t.height + 4 for t in tiles); W = max(t.width for t in tiles)
canvas = Image.new("RGB", (W, H), "white"); y = 0
for t in tiles:
    canvas.paste(t, (0, y)); y += t.height + 4
canvas.save(out)
