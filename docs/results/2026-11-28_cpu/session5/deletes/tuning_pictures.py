# ruff: noqa: E402, E501, E701, E702
"""Tuning pictures (seeds 33 and 31, oracle: ground-truth geometry): input, target (the scene rendered without the
car and its shadow), main's rule (every shadowed road pixel kept out of the rays' sources, no ray_marks; patched in)
and this branch, cropped around the deleted car, labelled with the PSNR on vacated region + shadow band.

usage: tuning_pictures.py OUT.png ROOT:KEY [ROOT:KEY ...]
"""
import math
import sys
from pathlib import Path

import numpy as np
import torch
from PIL import Image

import sdn3d.editing.photo.transfer as T
from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.visualize import titled_row

torch.set_num_threads(1)
ground = T._ground_rows
rows = []
for spec in sys.argv[2:]:
    root, key = spec.rsplit(":", 1)
    index = load_pairs(Path(root)); size = index.image_size
    p = next(p for p in index.pairs if p.kind == "delete" and p.key.startswith(key))
    rec = next(r for r in read_frames(Path(root), worlds=[p.world]) if (r.variation, r.frame) == (p.variation, p.frame))
    image = load_frame(rec, size, semantic=False, instances=False).image
    scene = scene_from_frame(rec, size); frame = PixelFrame(size, size)
    target = torch.from_numpy(load_pair_rgb(Path(root), p)).permute(2, 0, 1).float() / 255
    hole = torch.from_numpy(load_pair_mask(Path(root), p, "vacated")) | torch.from_numpy(load_pair_mask(Path(root), p, "shadow"))
    edited = apply_edits(scene, [Delete(p.instance_id)])
    pics = {}
    for name, st, rule in (("main's rule", PhotoSettings(ray_marks=0.0), lambda m, h, s: m), ("this branch", PhotoSettings(), ground)):
        T._ground_rows = rule
        pics[name] = T.render_photo(image, frame, scene, edited, settings=st).image.float().clamp(0, 1)
    T._ground_rows = ground
    ys, xs = hole.nonzero(as_tuple=True)
    y0, y1 = max(int(ys.min()) - 20, 0), min(int(ys.max()) + 20, size[1])
    x0, x1 = max(int(xs.min()) - 40, 0), min(int(xs.max()) + 40, size[0])
    def psnr(a, target=target, hole=hole): return 10 * math.log10(1 / max(float(((a - target)[:, hole] ** 2).mean()), 1e-6))
    tiles = [(f"input {p.key[:22]}", image), ("target (no car, no shadow)", target)] + [(f"{n} {psnr(x):.2f} dB", x) for n, x in pics.items()]
    rows.append(titled_row([(t, (x[:, y0:y1, x0:x1].permute(1, 2, 0).numpy() * 255).astype(np.uint8)) for t, x in tiles]))
width = max(r.shape[1] for r in rows)
grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
Image.fromarray(grid).quantize(256, dither=Image.Dither.NONE).save(sys.argv[1], optimize=True)
print(sys.argv[1])
