"""real_wagon.py REAL_DIR OUT_PNG [ZOOM_PNG]: close-ups of the real frame's red wagon (12001, README's box) turned
90 and 180 degrees from real_turns.py's outputs (REAL_DIR/{main,branch}/car0_turned_{90,180}/edited.png and
maps/photo_source.png), one row per turn: main's picture, the branch's, the pixels that differ (white), main's and
the branch's source maps; every panel titled with what it is and which code; scaled 2x. ZOOM_PNG: where the two
differ, 4x: the 180 turn's lower front and the 90 turn's front corner, main, branch and the pixels that differ.

    /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session25/back41/real_wagon.py /tmp/s25data/back41/real \\
        docs/results/2026-11-30_cpu/session25/back41/real_wagon_main_vs_5c1e23e.png
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

CROP = (430, 175, 720, 345)  # around the wagon's box [466, 203, 666, 333] and where its turns reach
CODES = {"main": "main 9a61b5b", "branch": "branch 5c1e23e"}


def load(path: Path) -> np.ndarray:
    image = Image.open(path).convert("RGB").crop(CROP)
    return np.asarray(image.resize((2 * image.width, 2 * image.height), Image.NEAREST))


def main() -> int:
    real, out = Path(sys.argv[1]), Path(sys.argv[2])
    rows = []
    for deg in (90, 180):
        pictures = {c: load(real / c / f"car0_turned_{deg}" / "edited.png") for c in CODES}
        maps = {c: load(real / c / f"car0_turned_{deg}" / "maps" / "photo_source.png") for c in CODES}
        differ = (pictures["main"] != pictures["branch"]).any(-1)
        diff = np.where(differ[..., None], 255, 0).astype(np.uint8).repeat(3, -1)
        rows.append(titled_row([
            (f"wagon 12001 turned {deg}: {CODES['main']}", pictures["main"]),
            (f"wagon 12001 turned {deg}: {CODES['branch']}", pictures["branch"]),
            (f"pixels that differ ({int(differ.sum()) // 4})", diff),
            (f"source map: {CODES['main']}", maps["main"]),
            (f"source map: {CODES['branch']}", maps["branch"])]))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).save(out)
    if len(sys.argv) > 3:
        rows = []
        for deg, (x0, y0, x1, y1) in ((180, (470, 270, 660, 340)), (90, (690, 230, 800, 330))):
            full = {c: np.asarray(Image.open(real / c / f"car0_turned_{deg}" / "edited.png").convert("RGB"))
                    for c in CODES}
            crops = {c: np.asarray(Image.fromarray(full[c][y0:y1, x0:x1]).resize((4 * (x1 - x0), 4 * (y1 - y0)),
                                                                              Image.NEAREST)) for c in CODES}
            differ = (crops["main"] != crops["branch"]).any(-1)
            diff = np.where(differ[..., None], 255, 0).astype(np.uint8).repeat(3, -1)
            rows.append(titled_row([(f"wagon turned {deg}, 4x: {CODES['main']}", crops["main"]),
                                    (f"wagon turned {deg}, 4x: {CODES['branch']}", crops["branch"]),
                                    ("pixels that differ", diff)]))
        width = max(r.shape[1] for r in rows)
        Image.fromarray(np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255)
                                        for r in rows])).save(sys.argv[3])
    return 0


if __name__ == "__main__":
    sys.exit(main())
