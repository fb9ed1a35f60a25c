# ruff: noqa: E402, E501, E701, E702
"""Before/after crops (2x, nearest) of the real frame's two defects, labelled panels.

usage: figure.py DATA OUT.png KEYS  (KEYS: comma-separated rows among rec,rot,rec1,rot2; DATA holds one.sh output dirs: rec_base, rec_new (12002 recoloured blue),
rot_base, rot_new (12001 turned 180), rec1_base, rec1_new (12001 recoloured blue), rot2_base, rot2_new (12002 turned 180))
"""
import sys

from PIL import Image, ImageDraw

data, out, keys = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
rows = [
    ("12002 (black) recoloured blue", (690, 180, 930, 315), "rec"),
    ("12001 (red) turned 180 deg", (450, 180, 690, 350), "rot"),
    ("12001 (red) recoloured blue", (450, 190, 690, 345), "rec1"),
    ("12002 (black) turned 180 deg", (680, 170, 950, 320), "rot2"),
]
panels = []
for title, box, key in [r for r in rows if r[2] in keys]:
    row = []
    for label, path in ((f"{title}: before (main a03af56)", f"{data}/{key}_base/out/edited.png"),
                        (f"{title}: after (s9-realparts)", f"{data}/{key}_new/out/edited.png"),
                        ("after: source map", f"{data}/{key}_new/out/maps/photo_source.png")):
        im = Image.open(path).convert("RGB").crop(box)
        im = im.resize((im.width * 2, im.height * 2), Image.NEAREST)
        c = Image.new("RGB", (im.width, im.height + 16), "white")
        c.paste(im, (0, 16))
        ImageDraw.Draw(c).text((3, 2), label, fill="black")
        row.append(c)
    panels.append(row)
width = max(sum(p.width for p in r) + 4 * (len(r) - 1) for r in panels)
height = sum(max(p.height for p in r) + 4 for r in panels)
sheet = Image.new("RGB", (width, height), "white")
y = 0
for r in panels:
    x = 0
    for p in r:
        sheet.paste(p, (x, y))
        x += p.width + 4
    y += max(p.height for p in r) + 4
scale = min(1.0, 1200 / sheet.width)
sheet = sheet.resize((int(sheet.width * scale), int(sheet.height * scale)), Image.LANCZOS)
sheet.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(out, optimize=True)  # records stay under 300 KB
