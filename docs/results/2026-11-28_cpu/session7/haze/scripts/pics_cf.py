# ruff: noqa: E402, E501, E701, E702
"""Before/after fills on counterfactual deletes (ground-truth geometry): input, truth (the frame rendered without the
car), ray_haze off, always on (no fog check: ray_haze_airlight=1), gated (this branch's defaults); crops around the
hole, 3x. usage: pics_cf.py OUT.png ROOT:KEY ..."""
import math
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image, ImageDraw

import sdn3d.editing.photo.transfer as T
from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings

torch.set_num_threads(1)
out, specs = sys.argv[1], sys.argv[2:]
variants = [("off (ray_haze 0)", PhotoSettings(ray_haze=0.0)), ("always on (airlight check off)", PhotoSettings(ray_haze_airlight=1.0)), ("gated (final)", PhotoSettings())]
strips = []
for spec in specs:
    root, key = spec.split(":")
    root = Path(root); index = load_pairs(root); size = index.image_size
    p = next(p for p in index.pairs if p.key.split()[0] == key and p.kind == "delete")
    rec = next(r for r in read_frames(root, worlds=[p.world]) if (r.variation, r.frame) == (p.variation, p.frame))
    image = load_frame(rec, size, semantic=False, instances=False).image
    scene = scene_from_frame(rec, size); frame = PixelFrame(size, size)
    target = torch.from_numpy(load_pair_rgb(root, p)).permute(2, 0, 1).float() / 255
    hole = torch.from_numpy(load_pair_mask(root, p, "vacated")) | torch.from_numpy(load_pair_mask(root, p, "shadow"))
    ys, xs = hole.nonzero(as_tuple=True)
    pad = 12; y0, y1 = max(0, int(ys.min()) - pad), min(size[1], int(ys.max()) + pad + 1); x0, x1 = max(0, int(xs.min()) - pad), min(size[0], int(xs.max()) + pad + 1)
    panels = [("input", image), ("truth", target)]
    for name, st in variants:
        pic = T.render_photo(image, frame, scene, apply_edits(scene, [Delete(p.instance_id)]), settings=st, source=T.PhotoSource(image, frame, scene, settings=st, max_fills=0)).image.float().clamp(0, 1)
        mse = float(((pic - target)[:, hole] ** 2).mean())
        panels.append((f"{name} {10 * math.log10(1 / max(mse, 1e-6)):.1f} dB", pic))
    scale = 3 if (x1 - x0) < 150 else 2
    tiles = []
    for name, img in panels:
        a = (img[:, y0:y1, x0:x1].permute(1, 2, 0).numpy() * 255).astype(np.uint8)
        t = Image.fromarray(a).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST)
        c = Image.new("RGB", (t.width, t.height + 14), "white"); c.paste(t, (0, 14)); ImageDraw.Draw(c).text((2, 1), name, fill="black")
        tiles.append(c)
    w = sum(t.width for t in tiles) + 4 * len(tiles); h = max(t.height for t in tiles) + 14
    strip = Image.new("RGB", (w, h), "white"); ImageDraw.Draw(strip).text((2, 1), f"{key} ({root.name})", fill="black")
    x = 0
    for t in tiles: strip.paste(t, (x, 14)); x += t.width + 4
    strips.append(strip)
W = max(s.width for s in strips); H = sum(s.height for s in strips)
sheet = Image.new("RGB", (W, H), "white"); y = 0
for s in strips: sheet.paste(s, (0, y)); y += s.height
sheet.save(out, optimize=True); print(out, sheet.size)
