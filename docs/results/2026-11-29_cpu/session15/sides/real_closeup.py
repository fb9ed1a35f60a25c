"""real_closeup.py MAIN_DIR BRANCH_DIR OUT.png: the real frame's edits that differ between two codes (outputs of session
12's realframe/probe.py), each cropped around the changed pixels (with a margin) and enlarged 4 times: main, branch
and |branch - main| x4, each panel titled."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image


def main() -> int:
    from sdn3d.visualize import titled_row

    base, new, out = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    rows = []
    for path in sorted(base.glob("*.png")):
        a = np.asarray(Image.open(path).convert("RGB"))
        b = np.asarray(Image.open(new / path.name).convert("RGB"))
        changed = np.abs(a.astype(int) - b.astype(int)).max(2) > 2
        if not changed.any():
            continue
        ys, xs = np.nonzero(changed)
        y0, y1 = max(0, ys.min() - 30), min(a.shape[0], ys.max() + 31)
        x0, x1 = max(0, xs.min() - 40), min(a.shape[1], xs.max() + 41)
        diff = np.clip(np.abs(a.astype(int) - b.astype(int)) * 4, 0, 255).astype(np.uint8)
        size = ((x1 - x0) * 4, (y1 - y0) * 4)
        panels = [(f"{path.stem}: {name}", np.asarray(Image.fromarray(np.ascontiguousarray(img[y0:y1, x0:x1]))
                                                        .resize(size, Image.NEAREST)))
                  for name, img in (("main", a), ("branch", b), ("|branch - main| x4", diff))]
        rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).save(out, optimize=True)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
