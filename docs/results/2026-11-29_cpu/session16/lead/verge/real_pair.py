# ruff: noqa: E501
"""real_pair.py BASE NEW OUT: the real frame's black car (12002) edits that differ, session start (BASE) above and
this change (NEW) below, cropped around the car, every panel titled."""
import sys

from PIL import Image, ImageDraw

base, new, out = sys.argv[1:4]
box = (640, 160, 1000, 340)
names = ["12002_deleted", "12002_turned_45", "12002_turned_90", "12002_turned_180"]
s = 2
w, h = (box[2] - box[0]) * s, (box[3] - box[1]) * s
img = Image.new("RGB", (w * len(names), (h + 18) * 2), "white")
d = ImageDraw.Draw(img)
for r, (root, label) in enumerate([(base, "session start"), (new, "verge runs")]):
    for c, n in enumerate(names):
        tile = Image.open(f"{root}/{n}.png").convert("RGB").crop(box).resize((w, h), Image.NEAREST)
        img.paste(tile, (c * w, r * (h + 18) + 18))
        d.text((c * w + 4, r * (h + 18) + 3), f"{n.replace('12002_', 'black car ')}: {label}", fill="black")
img.save(out)
