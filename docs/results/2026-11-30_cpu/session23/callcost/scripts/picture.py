"""Labelled before/after picture of same_outputs.sh's OUT: per call, one tree's and another's picture and their
absolute difference x10 (black: no pixel differs), each panel titled with the call and the code (session 22
fitcost's picture.py, the codes named on the command line).

    PYTHONPATH=src python picture.py OUT PICTURE.png NAME_A=LABEL_A NAME_B=LABEL_B
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

CALLS = (("bench", "edited.png", "benchmark call (10 boxes, car 12005 turned 30 deg)", None),
         ("real_turn90", "edited.png", "real frame: car 12001 turned 90 deg", (380, 130, 1000, 375)),
         ("real_delete", "edited.png", "real frame: car 12002 deleted", (380, 130, 1000, 375)),
         ("real_blue", "edited.png", "real frame: car 12001 recoloured blue", (380, 130, 1000, 375)),
         ("real_listed", "objects.png", "real frame: the listing (masks, fit IoU)", (380, 130, 1000, 375)))


def main() -> None:
    out, target = Path(sys.argv[1]), Path(sys.argv[2])
    (a, label_a), (b, label_b) = (arg.split("=", 1) for arg in sys.argv[3:5])
    rows = []
    for call, name, what, crop in CALLS:
        pics = [Image.open(out / side / call / name).convert("RGB") for side in (a, b)]
        if crop is not None:
            pics = [p.crop(crop) for p in pics]
        first, second = (np.asarray(p) for p in pics)
        diff = np.clip(np.abs(first.astype(int) - second.astype(int)) * 10, 0, 255).astype(np.uint8)
        changed = int((first != second).any(2).sum())
        rows.append(titled_row([(f"{what}: {label_a}", first), (f"{what}: {label_b}", second),
                                (f"|main - branch| x10: {changed} pixels differ", diff)]))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    image = Image.fromarray(grid)
    if image.width > 1150:
        image = image.resize((1150, round(image.height * 1150 / image.width)), Image.LANCZOS)
    image.quantize(256).save(target, optimize=True)  # a palette: the records keep pictures small
    print(target, image.size)


if __name__ == "__main__":
    main()
