# ruff: noqa: E501
"""real_figure.py OUT.png MAIN_PROBE BRANCH_PROBE: the real frame of tests/data (a box per car, the session 11 demo's
weights), each car deleted (session 12's realframe/probe.py outputs NNNNN_deleted.png), one row per car: the input,
main's delete and the branch's, cropped around the car's box at twice the size, each panel titled; a last line says
whether the two deletes are byte-identical."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
CARS = {12001: ("red car", (466, 203, 666, 333)), 12002: ("black car", (704, 194, 917, 305))}
MARGIN, SCALE = 30, 2


def main() -> int:
    out, main_dir, branch_dir = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    frame = Image.open(FRAME).convert("RGB")
    rows = []
    for iid, (name, (x0, y0, x1, y1)) in CARS.items():
        box = (max(x0 - MARGIN, 0), max(y0 - MARGIN, 0), min(x1 + MARGIN, frame.width), min(y1 + MARGIN, frame.height))
        main_pic = Image.open(main_dir / f"{iid}_deleted.png").convert("RGB")
        branch_pic = Image.open(branch_dir / f"{iid}_deleted.png").convert("RGB")
        same = np.array_equal(np.asarray(main_pic), np.asarray(branch_pic))
        tiles = []
        for title, pic in ((f"input ({name} {iid}, its box)", frame), (f"main (d47d803): {name} deleted", main_pic),
                           (f"branch (6d1ee02): {name} deleted" + (" (= main, byte-identical)" if same else ""), branch_pic)):
            crop = pic.crop(box)
            crop = crop.resize((crop.width * SCALE, crop.height * SCALE), Image.NEAREST)
            tile = Image.new("RGB", (crop.width, crop.height + 16), "white")
            tile.paste(crop, (0, 16))
            ImageDraw.Draw(tile).text((2, 2), title, fill="black")
            tiles.append(tile)
        row = Image.new("RGB", (sum(t.width + 6 for t in tiles), tiles[0].height), "white")
        x = 0
        for t in tiles:
            row.paste(t, (x, 0))
            x += t.width + 6
        rows.append(row)
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
