"""pictures.py MAIN_REAL BRANCH_REAL OUT.png [BRANCH_NAME]: the real frame's turns (session 12's probe outputs,
``ID_turned_DEG.png``) of main and of the branch side by side, cropped around the turned car, with the pixels that
differ (white where any channel differs by more than 2 of 255, grown by 3 pixels so that a single pixel shows), every
panel titled; prints per turn how many pixels differ and by how much."""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

main_dir, branch_dir, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
NAME = sys.argv[4] if len(sys.argv) > 4 else "branch"  # the branch panels' title
BOXES = {12001: (466, 203, 666, 333), 12002: (704, 194, 917, 305)}  # README's boxes (x0, y0, x1, y1)
turns = [(i, d) for i in BOXES for d in (45, 90, 180)]


def grown(mask: np.ndarray, r: int = 3) -> np.ndarray:
    from scipy.ndimage import binary_dilation

    return binary_dilation(mask, iterations=r)



fig, axes = plt.subplots(len(turns), 3, figsize=(12, 2.2 * len(turns)))
for (iid, deg), row in zip(turns, axes, strict=True):
    a = np.asarray(Image.open(main_dir / f"{iid}_turned_{deg}.png").convert("RGB")).astype(np.int16)
    b = np.asarray(Image.open(branch_dir / f"{iid}_turned_{deg}.png").convert("RGB")).astype(np.int16)
    diff = np.abs(a - b).max(2)
    x0, y0, x1, y1 = BOXES[iid]
    pad = 60
    ys, xs = slice(max(y0 - pad, 0), min(y1 + pad, a.shape[0])), slice(max(x0 - pad, 0), min(x1 + pad, a.shape[1]))
    changed = int((diff > 2).sum())
    print(f"car {iid} turned {deg}: {int((diff > 0).sum())} pixels differ, {changed} by more than 2/255, "
          f"max {int(diff.max())}/255, mean over those {float(diff[diff > 2].mean()) if changed else 0:.1f}/255")
    for ax, img, title in ((row[0], a[ys, xs], f"main 73c0792: car {iid} turned {deg} deg"),
                           (row[1], b[ys, xs], f"{NAME}: car {iid} turned {deg} deg"),
                           (row[2], np.repeat(grown(diff[ys, xs] > 2)[..., None] * 255, 3, 2),
                            f"differ by > 2/255: {changed} px (grown 3 px to show)")):
        ax.imshow(img.astype(np.uint8))
        ax.set_title(title, fontsize=8)
        ax.axis("off")
fig.tight_layout()
tmp = out.with_suffix(".tmp.png")
fig.savefig(tmp, dpi=55)
tmp.replace(out)
