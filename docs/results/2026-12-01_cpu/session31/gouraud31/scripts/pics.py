# ruff: noqa: E402, E501, E701, E702
"""pics.py OUT DIR:LABEL [DIR:LABEL ...]: the real frame's two cars turned -90 degrees (diag_real.py's outputs), one row
per run: the cars' crop of edited.png and of the photo source map (maps/photo_source.png: light cyan = part, dark cyan =
another car, green = photo, blue = mirror, yellow = fill), then a 3x zoom of each run's red car flank; every panel
labelled. (session 29's, any number of runs.)"""
import sys

from PIL import Image, ImageDraw

OUT = sys.argv[1]
runs = [a.split(":", 1) for a in sys.argv[2:]]
CROP, FLANK = (420, 170, 960, 360), (430, 200, 680, 330)


def label(im, text):
    d = ImageDraw.Draw(im)
    d.rectangle((0, 0, 8 + 6 * len(text), 13), fill="white")
    d.text((3, 1), text, fill="black")
    return im


w0, h0 = CROP[2] - CROP[0], CROP[3] - CROP[1]
zw, zh = 3 * (FLANK[2] - FLANK[0]), 3 * (FLANK[3] - FLANK[1])
n = len(runs)
sheet = Image.new("RGB", (max(2 * w0 + 10, zw), n * (h0 + 5) + n * (zh + 5) + 10), "white")
for i, (d, name) in enumerate(runs):
    ed = Image.open(f"{d}/edited.png").convert("RGB")
    src = Image.open(f"{d}/maps/photo_source.png").convert("RGB")
    sheet.paste(label(ed.crop(CROP).copy(), f"{name}: both cars turned -90 deg"), (0, i * (h0 + 5)))
    sheet.paste(label(src.crop(CROP).copy(), f"{name}: photo source map (cyan = part)"), (w0 + 10, i * (h0 + 5)))
    zoom = ed.crop(FLANK).resize((zw, zh), Image.NEAREST)
    sheet.paste(label(zoom, f"{name}: red car's new side, 3x"), (0, n * (h0 + 5) + 10 + i * (zh + 5)))
sheet.save(OUT)
