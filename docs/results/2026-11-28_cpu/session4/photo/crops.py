"""Crop each panel of a bench example grid around a point, upscale: python crops.py GRID.png U V OUT.png [HALF]"""
import sys

import numpy as np
from PIL import Image

img = np.asarray(Image.open(sys.argv[1]).convert("RGB"))
u, v = float(sys.argv[2]) * 312 / 1242, float(sys.argv[3]) * 96 / 375
half = int(sys.argv[5]) if len(sys.argv) > 5 else 36
band = img.shape[0] - 96
panels = []
for k in range(5):
    x0 = k * (312 + 4) if img.shape[1] > 5 * 312 else k * 312
    p = img[band:, x0:x0 + 312]
    a, b = int(max(u - half, 0)), int(min(u + half, 312))
    c, d = int(max(v - half * 0.6, 0)), int(min(v + half * 0.6, 96))
    panels.append(np.pad(p[c:d, a:b], ((0, 0), (0, 2), (0, 0)), constant_values=255))
Image.fromarray(np.concatenate(panels, 1)).resize((sum(q.shape[1] for q in panels) * 4, panels[0].shape[0] * 4),
                                                  Image.NEAREST).save(sys.argv[4])
