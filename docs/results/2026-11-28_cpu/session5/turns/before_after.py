# ruff: noqa: E501
"""Before/after picture of the tuning turns (seed 33): for chosen target cars, rows 45 / 90 / 180 degrees, columns
input, target, main, this branch (default), this branch with photo.outline_grow=0.1, each panel titled.

    python before_after.py DIAG_MAIN DIAG_FINAL DIAG_GROW OUT.png K [K ...]

DIAG_*: diagnose.py output folders run with --png (their pair_KK_*.png: per turn bin a row of input | target | ours |
|error| | source map | part map).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row


def _panels(folder: Path, k: int) -> list[np.ndarray]:
    path = next(folder.glob(f"pair_{k:02d}_*.png"))
    grid = np.asarray(Image.open(path).convert("RGB"))
    rows = np.split(grid, 4, axis=0)
    return [np.split(r, 6, axis=1) for r in rows]


def main() -> int:
    main_dir, final_dir, grow_dir, out = (Path(a) for a in sys.argv[1:5])
    targets = [int(k) for k in sys.argv[5:]]
    rows = []
    for k in targets:
        a, b, c = _panels(main_dir, k), _panels(final_dir, k), _panels(grow_dir, k)
        for i, turn in ((1, 45), (2, 90), (3, 180)):
            rows.append(titled_row([(f"#{k} input", a[i][0]), (f"target, turned {turn}", a[i][1]),
                                    ("main (774bffb)", a[i][2]), ("branch, default", b[i][2]),
                                    ("branch, outline_grow 0.1", c[i][2])]))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 4), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    picture = Image.fromarray(grid)
    picture.quantize(256).save(out, optimize=True)
    print(out, picture.size)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
