# ruff: noqa: E501
"""turn_closeups.py BEFORE_DIR AFTER_DIR OUT.png: the black car's (12002, the strip's car1) turns 45, 90 and 180 and its
delete from two real-frame strips (session 4's poses/real_strip.py output dirs: car1_<edit>/edited.png), cropped
around the car: per edit a row of before (main) and after (this branch), each panel titled. The turns vacate road
behind the car, which the rays fill as a delete's."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.io import atomic_write
from sdn3d.visualize import titled_row

BOX = (620, 160, 960, 330)


def main() -> int:
    before, after = Path(sys.argv[1]), Path(sys.argv[2])
    rows = []
    for edit in ("turned_45", "turned_90", "turned_180", "deleted"):
        name = f"black car 12002 {edit.replace('_', ' ')}"
        pics = [(f"{name}: before (main)", before / f"car1_{edit}" / "edited.png"),
                (f"{name}: after (this branch)", after / f"car1_{edit}" / "edited.png")]
        rows.append(titled_row([(t, np.asarray(Image.open(p).convert("RGB").crop(BOX))) for t, p in pics]))
    picture = Image.fromarray(np.concatenate(rows, 0))
    atomic_write(sys.argv[3], lambda f: picture.save(f, format="PNG", optimize=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
