"""strip.py BEFORE_DIR AFTER_DIR OUT.png: the real frame's strip, before and after, from two probe.py outputs (the same
demo weights and boxes; BEFORE: main's code, AFTER: this branch's): per car a row of main's pictures and a row of this
branch's, columns the input and each edit (turned 45, 90, 180 degrees, recoloured blue, deleted), each panel titled
with the car, the code and the edit; cropped around the car as real_strip.py does, at 2/3 size."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = {12001: (466, 203, 666, 333), 12002: (704, 194, 917, 305)}
EDITS = ("turned_45", "turned_90", "turned_180", "recoloured_blue", "deleted")


def main() -> int:
    from sdn3d.visualize import titled_row

    before, after, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    frame = np.asarray(Image.open(FRAME).convert("RGB"))
    rows = []
    for iid, (x0, y0, x1, y1) in BOXES.items():
        pad = 60
        cx0, cy0, cx1, cy1 = max(0, x0 - pad), max(0, y0 - pad), min(1242, x1 + pad), min(375, y1 + pad)
        for code, folder in (("main", before), ("this branch", after)):
            panels = [(f"{iid}: input", frame[cy0:cy1, cx0:cx1])]
            for edit in EDITS:
                picture = np.asarray(Image.open(folder / f"{iid}_{edit}.png").convert("RGB"))
                panels.append((f"{iid} {code}: {edit.replace('_', ' ')}", picture[cy0:cy1, cx0:cx1]))
            rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    picture = Image.fromarray(grid)
    picture = picture.resize((picture.width * 2 // 3, picture.height * 2 // 3), Image.LANCZOS)
    picture.quantize(256).save(out, optimize=True)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
