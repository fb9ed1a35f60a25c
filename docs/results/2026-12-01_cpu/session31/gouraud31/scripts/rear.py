# ruff: noqa: E402, E501, E701, E702
"""rear.py OUT DIR:LABEL DIR:LABEL: the real frame's red car, rear half of its new side (x 640-770, y 200-330) at 4x,
side by side, labelled (session 31)."""
import sys

from PIL import Image, ImageDraw

box = (640, 200, 770, 330); Z = 4
tiles = []
for arg in sys.argv[2:]:
    d, n = arg.split(":", 1)
    t = Image.open(d + "/edited.png").convert("RGB").crop(box).resize(((box[2] - box[0]) * Z, (box[3] - box[1]) * Z), Image.NEAREST)
    dr = ImageDraw.Draw(t); s = f"{n}: red car's rear half of the new side, 4x (x 640-770)"; dr.rectangle((0, 0, 8 + 6 * len(s), 13), fill="white"); dr.text((3, 1), s, fill="black")
    tiles.append(t)
w, h = tiles[0].size
sh = Image.new("RGB", (len(tiles) * (w + 10) - 10, h), "white")
for i, t in enumerate(tiles): sh.paste(t, (i * (w + 10), 0))
sh.save(sys.argv[1])
