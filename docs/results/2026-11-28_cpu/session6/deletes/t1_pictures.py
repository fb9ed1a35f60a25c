# ruff: noqa: E501
"""Labelled crops (8x) of t1_31 entries around their edit region, from diag_t1.py npz dumps (ground-truth masks,
3D-SDN's picture): input, target (edit region outlined red), then one panel per run directory with its PSNR on the
edit region.   usage: t1_pictures.py OUT.png IDX,IDX DIR=LABEL [DIR=LABEL ...]"""
import sys

import cv2
import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

out, idx, runs = sys.argv[1], sys.argv[2].split(","), [a.split("=", 1) for a in sys.argv[3:]]
rows = []
for i in idx:
    ds = [(np.load(f"{d}/{i}_gt_derender.npz"), label) for d, label in runs]
    first = ds[0][0]
    reg = first["regions"]
    ys, xs = np.nonzero(reg)
    y0, y1, x0, x1 = max(ys.min() - 12, 0), ys.max() + 13, max(xs.min() - 24, 0), xs.max() + 25

    def crop(img, box=(y0, y1, x0, x1)):
        return cv2.resize(np.ascontiguousarray(img[box[0]:box[1], box[2]:box[3]]), None, fx=8, fy=8,
                          interpolation=cv2.INTER_NEAREST)

    tgt = first["target"].copy()
    edge = reg ^ cv2.erode(reg.astype(np.uint8), np.ones((3, 3))).astype(bool)
    tgt[edge] = (255, 0, 0)

    def psnr(img, target=first["target"], reg=reg):
        err = ((img.astype(float) - target.astype(float)) / 255) ** 2
        return 10 * np.log10(1 / max(err[reg].mean(), 1e-10))

    panels = [(f"t1_31 entry {i}: input", crop(first["source"])), ("target (edit region red)", crop(tgt))]
    panels += [(f"{label} {psnr(d['photo:3d-sdn']):.1f} dB", crop(d["photo:3d-sdn"])) for d, label in ds]
    rows.append(titled_row(panels))
width = max(r.shape[1] for r in rows)
grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
Image.fromarray(grid).quantize(256, dither=Image.Dither.NONE).save(out, optimize=True)
print(out, grid.shape)
