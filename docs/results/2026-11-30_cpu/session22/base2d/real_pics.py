"""real_pics.py MAIN.npz BRANCH.npz OUT.png: the real frame's two cars deleted by the 2D paste baseline on main and on
the branch (real_delete.py's outputs, 624x192 working size), each row: the source photo, main's 2D delete, the
branch's 2D delete, crops of both around the car (nearest-neighbour enlarged), each panel titled.
Run: /work/main/.venv/bin/python real_pics.py /tmp/s22data/base2d/real_main.npz /tmp/s22data/base2d/real_br.npz OUT.png
"""

from __future__ import annotations

import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main(main_npz: str, branch_npz: str, out: str) -> None:
    a, b = np.load(main_npz), np.load(branch_npz)
    titles = ("source photo (working size)", "2D paste delete, main 9b7f993", "2D paste delete, branch s22-base2d",
              "crop: main", "crop: branch")
    fig, axes = plt.subplots(2, len(titles), figsize=(20, 4.6), squeeze=False,
                             gridspec_kw={"width_ratios": [3.25] * 3 + [1.9, 1.9]})
    for r, (car, iid) in enumerate((("car0", 12001), ("car1", 12002))):
        ys, xs = np.nonzero(a["ids"] == iid)
        y0, y1 = max(int(ys.min()) - 20, 0), min(int(ys.max()) + 21, a["ids"].shape[0])
        x0, x1 = max(int(xs.min()) - 20, 0), min(int(xs.max()) + 21, a["ids"].shape[1])
        changed = int((a[car] != b[car]).any(-1).sum())
        panels = (a["source"], a[car], b[car], a[car][y0:y1, x0:x1], b[car][y0:y1, x0:x1])
        for c, (panel, title) in enumerate(zip(panels, titles, strict=True)):
            ax = axes[r, c]
            ax.imshow(panel, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(title + (f" ({changed} px differ)" if c == 2 else ""), fontsize=7)
        axes[r, 0].set_ylabel(f"car {iid} deleted", fontsize=7)
    fig.suptitle("The real Virtual KITTI frame (tests/data), demo weights w0: the 2D paste baseline's delete, main vs "
                 "branch (fill='rays')", fontsize=9)
    fig.tight_layout()
    tmp = f"{out}.tmp.png"
    fig.savefig(tmp, dpi=66)
    os.replace(tmp, out)


if __name__ == "__main__":
    main(*sys.argv[1:4])
