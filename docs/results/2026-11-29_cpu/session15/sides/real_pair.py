"""real_pair.py NAME=DIR [NAME=DIR ...] OUT.png: the real frame of tests/data edited by several codes (outputs of
session 12's realframe/probe.py): per car and edit (turned 45, 90 and 180 degrees, recoloured blue) a row of the
codes' pictures side by side, cropped around the car (session 14 ends2_real3.py's windows) at twice the size, each
panel titled with the car, the edit and the code."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

#: rows, columns around each car (the turned and the recoloured car fit in one window)
WINDOWS = {12001: (150, 345, 380, 720), 12002: (170, 330, 640, 960)}
EDITS = ("turned_45", "turned_90", "turned_180", "recoloured_blue")


def main() -> int:
    from sdn3d.visualize import titled_row

    *codes, out = sys.argv[1:]
    folders = [(c.split("=")[0], Path(c.split("=")[1])) for c in codes]
    rows = []
    for iid, (y0, y1, x0, x1) in WINDOWS.items():
        for edit in EDITS:
            panels = []
            for name, folder in folders:
                crop = np.asarray(Image.open(folder / f"{iid}_{edit}.png").convert("RGB"))[y0:y1, x0:x1]
                crop = np.asarray(Image.fromarray(crop).resize(((x1 - x0) * 2, (y1 - y0) * 2), Image.LANCZOS))
                panels.append((f"car {iid} {edit.replace('_', ' ')}: {name}", crop))
            rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).quantize(256).save(out, optimize=True)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
