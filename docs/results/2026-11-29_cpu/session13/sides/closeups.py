"""closeups.py MAIN_DIR BRANCH_DIR OUT.png: the real frame's turned cars at twice the size, from two outputs of session
12's probe.py (docs/results/2026-11-29_cpu/session12/realframe/probe.py; MAIN_DIR: main's code, BRANCH_DIR: this
branch's): per car and turn (45, 90, 180 degrees) a row of main's picture and this branch's, each panel titled."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

WINDOWS = {12001: (150, 345, 380, 720), 12002: (170, 330, 640, 960)}  # rows, columns around each turned car


def main() -> int:
    from sdn3d.visualize import titled_row

    before, after, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    rows = []
    for iid, (y0, y1, x0, x1) in WINDOWS.items():
        for turn in (45, 90, 180):
            panels = []
            for code, folder in (("main", before), ("this branch", after)):
                picture = np.asarray(Image.open(folder / f"{iid}_turned_{turn}.png").convert("RGB"))[y0:y1, x0:x1]
                picture = np.asarray(Image.fromarray(picture).resize(((x1 - x0) * 2, (y1 - y0) * 2), Image.LANCZOS))
                panels.append((f"car {iid} turned {turn}: {code}", picture))
            rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).quantize(256).save(out, optimize=True)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
