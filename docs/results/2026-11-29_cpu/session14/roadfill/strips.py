# ruff: noqa: E501
"""strips.py BEFORE.png AFTER.png OUT.png: two real-frame strips (session 4's poses/real_strip.py, one row per car: listed,
turned 45, 90, 180, recoloured blue, deleted; each panel titled by it) one above the other, each under a title
band naming its code: before = main (d56e075), after = this branch."""

from __future__ import annotations

import sys

import numpy as np
from PIL import Image

from sdn3d.io import atomic_write
from sdn3d.visualize import titled_panel


def main() -> int:
    before, after = (np.asarray(Image.open(p).convert("RGB")) for p in sys.argv[1:3])
    rows = [titled_panel(before, "before: main (d56e075), photo.fill=rays", 22),
            titled_panel(after, "after: this branch (add65da), photo.fill=rays, photo.ray_verge=road", 22)]
    width = max(r.shape[1] for r in rows)
    rows = [np.concatenate([r, np.full((r.shape[0], width - r.shape[1], 3), 255, np.uint8)], 1) for r in rows]
    picture = Image.fromarray(np.concatenate(rows, 0)).quantize(256)
    atomic_write(sys.argv[3], lambda f: picture.save(f, format="PNG", optimize=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
