"""Texture of a delete on the real frame: mean absolute Laplacian (luma, 3x3) of the changed pixels that look like
road against the road-like pixels of a ring 8-40 px around them (unchanged), for each edited.png given.

usage: real_texture.py INPUT.png EDITED.png [EDITED.png ...]
"""

import sys

import cv2
import numpy as np
import torch
from PIL import Image

from sdn3d.editing.photo.road import road_colours, road_like
from sdn3d.image_ops import dilate_square

src = np.asarray(Image.open(sys.argv[1]).convert("RGB")).astype(np.float32) / 255
for path in sys.argv[2:]:
    out = np.asarray(Image.open(path).convert("RGB")).astype(np.float32) / 255
    changed = torch.from_numpy(np.abs(out - src).max(2) > 0)
    ring = dilate_square(changed, 40) & ~dilate_square(changed, 8)
    img = torch.from_numpy(out).permute(2, 0, 1)
    road = road_colours(img, ring)
    like = road_like(img, road, min_light=0.0) if road is not None else torch.ones_like(changed)
    lap = np.abs(cv2.Laplacian(out @ np.array([0.2126, 0.7152, 0.0722], np.float32), cv2.CV_32F, ksize=1))
    inside = (changed & like).numpy()
    around = (ring & like).numpy()
    a, b = float(lap[inside].mean()), float(lap[around].mean())
    print(
        f"{path}: delete region (road-like, {inside.sum()} px) {a:.4f}, surrounding road ({around.sum()} px) {b:.4f}, "
        f"ratio {a / b:.3f}"
    )
