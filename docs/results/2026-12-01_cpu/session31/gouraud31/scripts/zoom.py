# ruff: noqa: E402, E501, E701, E702
"""zoom.py OUT DIR:LABEL...: the real frame's windscreen front at 5x for each run, and the first run's part map."""
import sys

import numpy as np
from PIL import Image, ImageDraw

box = (450, 205, 560, 300); Z = 5
runs = [a.split(":", 1) for a in sys.argv[2:]]
PAL = {-1: (40, 40, 40), 0: (200, 60, 60), 1: (80, 160, 230), 2: (30, 30, 30), 3: (250, 250, 120), 4: (250, 120, 0), 5: (250, 250, 250)}
tiles = []
for d, name in runs:
    ed = Image.open(f"{d}/edited.png").convert("RGB")
    tiles.append((ed.crop(box).resize(((box[2]-box[0])*Z, (box[3]-box[1])*Z), Image.NEAREST), name))
mp = np.load(f"{runs[0][0]}/diag_maps.npz")
parts = mp["parts"].reshape(375, 1242)
src = mp["source"].reshape(375, 1242)
rgb = np.zeros((375, 1242, 3), np.uint8)
for k, c in PAL.items():
    rgb[parts == k] = c
rgb[(src != 7) & (src != 11) & (parts >= 0)] //= 2  # not part/another car: darker
tiles.append((Image.fromarray(rgb).crop(box).resize(((box[2]-box[0])*Z, (box[3]-box[1])*Z), Image.NEAREST), "parts (red body, blue glass; dim: not drawn from examples)"))
w, h = tiles[0][0].size
sheet = Image.new("RGB", (2 * w + 10, ((len(tiles) + 1) // 2) * (h + 5)), "white")
for i, (t, name) in enumerate(tiles):
    dr = ImageDraw.Draw(t); dr.rectangle((0, 0, 8 + 6 * len(name), 13), fill="white"); dr.text((3, 1), name, fill="black")
    sheet.paste(t, ((i % 2) * (w + 10), (i // 2) * (h + 5)))
sheet.save(sys.argv[1])
