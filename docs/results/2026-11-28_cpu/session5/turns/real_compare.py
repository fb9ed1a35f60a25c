"""The real frame's turned cars side by side: main, this branch (default) and this branch with
photo.outline_grow=0.1, crops of real_strip.py's edited.png per car and turn, each panel titled.

    python real_compare.py MAIN_STRIP FINAL_STRIP GROW_STRIP OUT.png
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

CROPS = {0: (slice(130, 350), slice(380, 760)), 1: (slice(150, 340), slice(600, 950))}


def main() -> int:
    runs = [("main", Path(sys.argv[1])), ("branch", Path(sys.argv[2])), ("branch, outline_grow 0.1", Path(sys.argv[3]))]
    out = Path(sys.argv[4])
    rows = []
    for car, crop in CROPS.items():
        for label, folder in runs:
            panels = []
            for turn in (45, 90, 180):
                image = np.asarray(Image.open(folder / f"car{car}_turned_{turn}" / "edited.png").convert("RGB"))
                panels.append((f"{12001 + car} turned {turn}: {label}", image[crop]))
            rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 4), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    picture = Image.fromarray(grid)
    picture = picture.resize((picture.width // 2, picture.height // 2), Image.LANCZOS)
    picture.quantize(256).save(out, optimize=True)
    print(out, picture.size)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
