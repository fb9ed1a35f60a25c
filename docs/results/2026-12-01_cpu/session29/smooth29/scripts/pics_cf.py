# ruff: noqa: E501
"""pics_cf.py OUT MAIN_DIR BRANCH_DIR KEY [KEY ...]: capture_cf.py's pictures of held-out turn pairs, main against the
branch: per key a row of the target, main's picture and the branch's, cropped to the car's target mask (margin 12 px)
at 3x, each panel labelled with its PSNR on the car's pixels (the benchmark's region)."""
import math
import sys

import numpy as np
from PIL import Image, ImageDraw

OUT, MAIN, BRANCH, *KEYS = sys.argv[1:]


def label(im, text):
    d = ImageDraw.Draw(im)
    d.rectangle((0, 0, 8 + 6 * len(text), 13), fill="white")
    d.text((3, 1), text, fill="black")
    return im


def psnr(a, b, m):
    mse = float((((a - b) ** 2).mean(-1))[m].mean())
    return 10 * math.log10(1 / max(mse, 1e-12))


rows = []
for key in KEYS:
    tgt = np.asarray(Image.open(f"{MAIN}/{key}_target.png").convert("RGB")) / 255.0
    mask = np.asarray(Image.open(f"{MAIN}/{key}_mask.png")) > 127
    ys, xs = np.nonzero(mask)
    box = (max(xs.min() - 12, 0), max(ys.min() - 12, 0), min(xs.max() + 13, mask.shape[1]), min(ys.max() + 13, mask.shape[0]))
    row = [label(Image.open(f"{MAIN}/{key}_target.png").convert("RGB").crop(box).resize(((box[2] - box[0]) * 3, (box[3] - box[1]) * 3), Image.NEAREST), f"{key}: target")]
    for name, d in (("main 2e90ef47", MAIN), ("branch e01c4444", BRANCH)):
        pic = Image.open(f"{d}/{key}_picture.png").convert("RGB")
        p = psnr(np.asarray(pic) / 255.0, tgt, mask)
        row.append(label(pic.crop(box).resize(((box[2] - box[0]) * 3, (box[3] - box[1]) * 3), Image.NEAREST), f"{name}: {p:.2f} dB on the car"))
    rows.append(row)
W = max(sum(im.width for im in r) + 10 * (len(r) - 1) for r in rows)
H = sum(r[0].height for r in rows) + 10 * (len(rows) - 1)
sheet = Image.new("RGB", (W, H), "white")
y = 0
for r in rows:
    x = 0
    for im in r:
        sheet.paste(im, (x, y))
        x += im.width + 10
    y += r[0].height + 10
sheet.save(OUT)
