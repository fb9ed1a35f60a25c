"""real_measure.py MAIN_DIR BRANCH_DIR: the real frame's edits (redraw.py outputs, NAME.npz) drawn by main and the
branch: per edit, the pixels the two codes draw differently, how many of those the branch draws as a verge and main
as road (verge_like against the road's Lab around the black car's hole, (58.4, -2.8, 15.1), the value ray_fill
received on this frame), the reverse, and the rest; and, for the black car's delete, where the verge the branch
draws inside main's hole lies (rows, columns).

    cd CODE_TREE && PYTHONPATH=src python real_measure.py /tmp/s21data/island/real_main /tmp/s21data/island/real_br
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import torch

from sdn3d.editing.photo.road import verge_like

ROAD = torch.tensor([58.3923, -2.8125, 15.1462])


def verge(picture: np.ndarray) -> np.ndarray:
    flat = torch.from_numpy(picture.reshape(-1, 3).T.astype(np.float32) / 255.0)
    return verge_like(flat, ROAD).numpy().reshape(picture.shape[:2])


def main() -> int:
    main_dir, branch_dir = Path(sys.argv[1]), Path(sys.argv[2])
    print("| edit | px drawn differently | verge in branch, road in main | road in branch, verge in main | other |")
    print("|---|---|---|---|---|")
    for path in sorted(main_dir.glob("*.npz")):
        a, b = (np.load(d / path.name)["edited"] for d in (main_dir, branch_dir))
        diff = np.any(a != b, axis=2)
        va, vb = verge(a), verge(b)
        gained, lost = diff & vb & ~va, diff & va & ~vb
        print(f"| {path.stem} | {int(diff.sum())} | {int(gained.sum())} | {int(lost.sum())} | "
              f"{int((diff & ~gained & ~lost).sum())} |")
        if path.stem == "12002_deleted" and gained.any():
            ys, xs = np.nonzero(gained)
            print(f"\nblack car's delete: verge gained in rows {ys.min()}-{ys.max()}, columns {xs.min()}-{xs.max()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
