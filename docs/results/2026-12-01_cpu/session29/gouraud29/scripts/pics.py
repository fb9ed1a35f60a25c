# ruff: noqa: E501
"""pics.py OUT MAIN_DIR BRANCH_DIR [LABEL_MAIN LABEL_BRANCH]: the real frame's two cars turned -90 degrees
(diag_real.py's outputs), main against the branch: the cars' crop of edited.png and of the photo source map
(maps/photo_source.png: light cyan = part, dark cyan = another car, green = photo, blue = mirror, yellow = fill), and a
3x zoom of the red car's flank; every panel labelled."""
import sys

from PIL import Image, ImageDraw

OUT, MAIN, BRANCH = sys.argv[1:4]
names = sys.argv[4:6] if len(sys.argv) > 5 else ["main bbdcb5ac", "branch (photo.part_smoothing)"]
CROP, FLANK = (420, 170, 960, 360), (430, 200, 680, 330)


def label(im, text):
    d = ImageDraw.Draw(im)
    d.rectangle((0, 0, 8 + 6 * len(text), 13), fill="white")
    d.text((3, 1), text, fill="black")
    return im


panels = []
for name, d in zip(names, (MAIN, BRANCH), strict=True):
    ed = Image.open(f"{d}/edited.png").convert("RGB")
    src = Image.open(f"{d}/maps/photo_source.png").convert("RGB")
    panels.append([label(ed.crop(CROP).copy(), f"{name}: both cars turned -90 deg"),
                   label(src.crop(CROP).copy(), f"{name}: photo source map (cyan = part)"),
                   label(ed.crop(FLANK).resize((3 * (FLANK[2] - FLANK[0]), 3 * (FLANK[3] - FLANK[1])), Image.NEAREST), f"{name}: red car's new side, 3x")])
w0, h0 = CROP[2] - CROP[0], CROP[3] - CROP[1]
zw, zh = 3 * (FLANK[2] - FLANK[0]), 3 * (FLANK[3] - FLANK[1])
sheet = Image.new("RGB", (max(2 * w0, 2 * zw) + 10, 2 * h0 + zh + 20), "white")
for i, (ed, src, zoom) in enumerate(panels):
    sheet.paste(ed, (0, i * (h0 + 5)))
    sheet.paste(src, (w0 + 10, i * (h0 + 5)))
    sheet.paste(zoom, (i * (zw + 10), 2 * h0 + 15))
sheet.save(OUT)
