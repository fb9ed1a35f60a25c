"""The real frame's two deletes (tests/data, boxes, demo weights) before and after, labelled: the input, the session's
start (5426919) and this branch, cropped around each car (session 6).

usage: real_before_after.py BEFORE_DIR AFTER_DIR OUT.png [AFTER2_DIR LABEL2]   (each DIR from session4's
real_deletes.py: DIR/car{0,1}_deleted/edited.png)
"""

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [(12001, "red car", [466, 203, 666, 333]), (12002, "black car", [704, 194, 917, 305])]
start, new, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
extra = [(Path(sys.argv[4]), sys.argv[5])] if len(sys.argv) > 5 else []
rows = []
for car, (iid, name, (x0, y0, x1, y1)) in enumerate(BOXES):
    crop = (max(0, x0 - 60), max(0, y0 - 60), min(1242, x1 + 60), min(375, y1 + 60))
    pictures = [FRAME, start / f"car{car}_deleted" / "edited.png", new / f"car{car}_deleted" / "edited.png"]
    titles = [f"input: {name} ({iid})", "deleted, session start (5426919)", "deleted, this branch (session 6)"]
    for d, label in extra:
        pictures.append(d / f"car{car}_deleted" / "edited.png")
        titles.append(label)
    rows.append(titled_row([(t, np.asarray(Image.open(p).convert("RGB").crop(crop)))
                            for t, p in zip(titles, pictures, strict=True)]))
width = max(r.shape[1] for r in rows)
grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
# a 256-colour palette keeps the PNG of the records small (under 300 KB)
Image.fromarray(grid).quantize(256, dither=Image.Dither.NONE).save(out, optimize=True)
print(out)
