# ruff: noqa: E501
"""closeups.py BEFORE_DIR AFTER_DIR OUT.png: the real frame's two deletes (session 12's realframe/probe.py outputs,
12001_deleted.png and 12002_deleted.png) before and after, cropped around each car and shown at twice the size: per car
a row of input, before (main, d56e075), after (this branch), each panel titled."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.io import atomic_write
from sdn3d.visualize import titled_row

FRAME = Path(__file__).resolve().parents[5] / "tests" / "data" / "0006_30-deg-right_00043.png"
CROPS = {12001: ("red car 12001", (440, 180, 720, 340)), 12002: ("black car 12002", (640, 175, 940, 335))}


def main() -> int:
    before, after, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    rows = []
    for iid, (name, box) in CROPS.items():
        size = ((box[2] - box[0]) * 2, (box[3] - box[1]) * 2)
        pics = [(f"input ({name})", Image.open(FRAME)), (f"{name} deleted: before (main)", Image.open(before / f"{iid}_deleted.png")),
                (f"{name} deleted: after (photo.ray_verge=road)", Image.open(after / f"{iid}_deleted.png"))]
        rows.append(titled_row([(t, np.asarray(p.convert("RGB").crop(box).resize(size, Image.NEAREST))) for t, p in pics]))
    width = max(r.shape[1] for r in rows)
    rows = [np.concatenate([r, np.full((r.shape[0], width - r.shape[1], 3), 255, np.uint8)], 1) for r in rows]
    picture = Image.fromarray(np.concatenate(rows, 0))
    atomic_write(out, lambda f: picture.save(f, format="PNG", optimize=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
