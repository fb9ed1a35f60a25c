"""real_figure.py MAIN_DIR BRANCH_DIR OUT.png [MAIN_LABEL BRANCH_LABEL]:
the real frame's deletes (redraw.py outputs, NAME.npz) drawn by main
and the branch, each car's delete a row: input, main, branch over the car's box (twice the size), then close-ups at
six times the size on the pixels the two codes drew differently (the shadow's tip), every panel titled.

    PYTHONPATH=src python real_figure.py /tmp/s21data/shade/real/main /tmp/s21data/shade/real/br2 OUT.png \
        "main (a1c700b)" "branch (0e79c64)"
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
#: README's boxes (x0, y0, x1, y1), grown for the shadow below.
BOXES = {"12001": ("red car", (430, 190, 690, 360)), "12002": ("black car", (680, 185, 940, 330))}


def panel(picture: np.ndarray, box: tuple[int, int, int, int], scale: int, title: str) -> Image.Image:
    x0, y0, x1, y1 = box
    crop = Image.fromarray(picture[y0:y1, x0:x1]).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST)
    out = Image.new("RGB", (crop.width, crop.height + 14), "white")
    out.paste(crop, (0, 14))
    ImageDraw.Draw(out).text((2, 1), title, fill="black")
    return out


def main() -> int:
    main_dir, branch_dir, target = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    main_label, branch_label = (sys.argv[4], sys.argv[5]) if len(sys.argv) > 5 else ("main", "branch")
    frame = np.array(Image.open(FRAME).convert("RGB"))
    rows = []
    for iid, (name, box) in BOXES.items():
        ours = np.load(branch_dir / f"{iid}_deleted.npz")["edited"]
        theirs = np.load(main_dir / f"{iid}_deleted.npz")["edited"]
        rows.append([panel(frame, box, 2, f"input ({name})"), panel(theirs, box, 2, f"{main_label}: {name} deleted"),
                     panel(ours, box, 2, f"{branch_label}: {name} deleted")])
        ys, xs = np.nonzero((ours != theirs).any(-1))
        if len(ys):
            cy, cx = (int(ys.min()) + int(ys.max())) // 2, (int(xs.min()) + int(xs.max())) // 2
            close = (cx - 25, cy - 15, cx + 25, cy + 15)
            rows.append([panel(frame, close, 6, f"input ({name}), close-up"),
                         panel(theirs, close, 6, f"{main_label}, close-up"),
                         panel(ours, close, 6, f"{branch_label}, close-up")])
    width = max(sum(p.width for p in r) + 6 * len(r) for r in rows)
    height = sum(max(p.height for p in r) + 6 for r in rows)
    sheet = Image.new("RGB", (width, height), "white")
    y = 0
    for r in rows:
        x = 0
        for p in r:
            sheet.paste(p, (x, y))
            x += p.width + 6
        y += max(p.height for p in r) + 6
    sheet.save(target, optimize=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
