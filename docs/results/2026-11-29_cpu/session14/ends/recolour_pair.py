"""recolour_pair.py MAIN_DIR BRANCH_DIR OUT.png: the real frame's recoloured cars (session 12's probe.py pictures),
main's and this branch's side by side at twice the size, each panel titled."""

from __future__ import annotations

import sys

import numpy as np
from PIL import Image, ImageDraw

WINDOWS = {12001: (180, 345, 440, 700), 12002: (170, 320, 680, 940)}  # rows, columns around each car


def main() -> None:
    main_dir, branch_dir, out = sys.argv[1:4]
    rows = []
    for iid, (r0, r1, c0, c1) in WINDOWS.items():
        tiles = []
        for name, d in (("main", main_dir), ("this branch", branch_dir)):
            img = np.asarray(Image.open(f"{d}/{iid}_recoloured_blue.png").convert("RGB"))[r0:r1, c0:c1]
            t = Image.fromarray(np.ascontiguousarray(img)).resize(((c1 - c0) * 2, (r1 - r0) * 2), Image.NEAREST)
            tile = Image.new("RGB", (t.width, t.height + 16), "white")
            tile.paste(t, (0, 16))
            ImageDraw.Draw(tile).text((2, 2), f"car {iid} recoloured blue: {name}", fill=(0, 0, 0))
            tiles.append(tile)
        row = Image.new("RGB", (sum(t.width + 6 for t in tiles), tiles[0].height), "white")
        x = 0
        for t in tiles:
            row.paste(t, (x, 0))
            x += t.width + 6
        rows.append(row)
    canvas = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 6 for r in rows)), "white")
    y = 0
    for r in rows:
        canvas.paste(r, (0, y))
        y += r.height + 6
    canvas.save(out)


if __name__ == "__main__":
    main()
