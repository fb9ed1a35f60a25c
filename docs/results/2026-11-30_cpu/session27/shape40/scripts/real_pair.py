"""real_pair.py MAIN_STRIP BRANCH_STRIP OUT.png: the real frame's two box cars listed and turned 45, 90 and 180 degrees,
main's row above the branch's for each car, every panel titled with its code, car, op and the template listed: panels
from issue40_41/real_strip.py's outputs of each code (its per-edit folders; run w0, ``proposals=boxes``). Run with a
library on PYTHONPATH (sdn3d.visualize)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image

BOXES = [[466, 203, 666, 333], [704, 194, 917, 305]]
EDITS = ["listed", "turned 45", "turned 90", "turned 180"]
SCALE = 0.6  # the picture's size (kept under ~400 KB)


def main() -> int:
    from sdn3d.visualize import titled_row

    strips = {"main 9bee856": Path(sys.argv[1]), "branch 9b5672a": Path(sys.argv[2])}
    rows = []
    for car, (iid, box) in enumerate(zip((12001, 12002), BOXES, strict=True)):
        x0, y0, x1, y1 = box
        crop = (max(0, x0 - 60), max(0, y0 - 60), min(1242, x1 + 60), min(375, y1 + 60))
        for code, strip in strips.items():
            listing = json.loads((strip / "listing.json").read_text())[str(iid)]["objects"]
            template = next(o["template"] for o in listing if o["id"] == iid)
            panels = []
            for title in EDITS:
                folder = strip / f"car{car}_{title.replace(' ', '_')}"
                picture = folder / ("objects.png" if title == "listed" else "edited.png")
                image = Image.open(picture).convert("RGB").crop(crop)
                image = image.resize((int(image.width * SCALE), int(image.height * SCALE)), Image.LANCZOS)
                op = title.replace("turned", "turn")
                panels.append((f"{code}: {iid} {op} ({template})", np.asarray(image)))
            rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).quantize(256).save(sys.argv[3])  # a palette keeps it under ~400 KB
    print(sys.argv[3])
    return 0


if __name__ == "__main__":
    sys.exit(main())
