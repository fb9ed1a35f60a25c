"""real_figure.py OUT.png MAIN_DIR BRANCH_DIR [MAIN_LABEL BRANCH_LABEL] [EDIT]: the real frame of tests/data (a box per
car, this session's demo weights) with each car's EDIT (deleted: default; turned_90), main's picture against the
branch's (probe.py or redraw.py outputs NNNNN_EDIT.png): one row per car, the input, main's and the branch's picture
cropped around the car's box at twice the size, then one close-up row per car at six times the size around its side
mirror (the black car's: rows 205-235, columns 712-752; the red car's: rows 215-255, columns 450-500), every panel
titled (what, which code). Run from anywhere (needs numpy and PIL only)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
CARS = {12001: ("red car", (466, 203, 666, 333), (450, 215, 500, 255)),
        12002: ("black car", (704, 194, 917, 305), (712, 205, 752, 235))}
MARGIN = 30


def tile(picture: Image.Image, box: tuple[int, int, int, int], scale: int, title: str) -> Image.Image:
    crop = picture.crop(box)
    crop = crop.resize((crop.width * scale, crop.height * scale), Image.NEAREST)
    out = Image.new("RGB", (max(crop.width, 6 * len(title) + 4), crop.height + 14), "white")
    out.paste(crop, (0, 14))
    ImageDraw.Draw(out).text((2, 1), title, fill="black")
    return out


def row(tiles: list[Image.Image]) -> Image.Image:
    out = Image.new("RGB", (sum(t.width + 6 for t in tiles), max(t.height for t in tiles)), "white")
    x = 0
    for t in tiles:
        out.paste(t, (x, 0))
        x += t.width + 6
    return out


def main() -> int:
    out, main_dir, branch_dir = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    main_label, branch_label = (sys.argv[4], sys.argv[5]) if len(sys.argv) > 5 else ("main", "branch")
    edit = sys.argv[6] if len(sys.argv) > 6 else "deleted"
    what = edit.replace("_", " by ") + (" degrees" if "turned" in edit else "")
    frame = Image.open(FRAME).convert("RGB")
    rows = []
    for scale, which in ((2, 1), (6, 2)):
        for iid, spec in CARS.items():
            name, (x0, y0, x1, y1) = spec[0], spec[1]
            box = spec[2] if which == 2 else (max(x0 - MARGIN, 0), max(y0 - MARGIN, 0), min(x1 + MARGIN, frame.width),
                                               min(y1 + MARGIN, frame.height))
            m = Image.open(main_dir / f"{iid}_{edit}.png").convert("RGB")
            b = Image.open(branch_dir / f"{iid}_{edit}.png").convert("RGB")
            same = " (= main, byte-identical)" if np.array_equal(np.asarray(m), np.asarray(b)) else ""
            part = "its box" if which == 1 else "its left mirror, close-up"
            rows.append(row([tile(frame, box, scale, f"input ({name}, {part})"),
                             tile(m, box, scale, f"{main_label}: {name} {what}"),
                             tile(b, box, scale, f"{branch_label}: {name} {what}{same}")]))
    sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 8 for r in rows)), "white")
    y = 0
    for r in rows:
        sheet.paste(r, (0, y))
        y += r.height + 8
    sheet.save(out)
    print(out, sheet.size)
    return 0


if __name__ == "__main__":
    sys.exit(main())
