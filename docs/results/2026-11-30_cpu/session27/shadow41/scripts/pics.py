"""pics.py MAIN_DIR BRANCH_DIR OUT.png LABEL KEY [KEY ...]: before/after pictures of counterfactual deletes from
diag.py's dumps of main and of the branch (same pairs): per pair one row, cropped around the removed car and its
shadow band: the input, the target (exact render without the car), main's photo:rays result, the branch's, main's
masks and the branch's (the hole before the shadow joined: yellow; the dark shadow joined to it: orange; shadow
pieces past it: red; the branch's relit faint shadow: green; the true shadow band's outline: cyan, ground truth,
an oracle shown only to judge). KEY: the dump's file stem (``semantic_0006+clone+...``). Each row's title gives the
pair, the source scene and the darkening of main / branch / target in the band."""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.ndimage import binary_dilation, binary_erosion  # noqa: E402

LUMA = np.array([0.2126, 0.7152, 0.0722])


def darkening(img: np.ndarray, band: np.ndarray, ring: np.ndarray) -> float:
    y = np.tensordot(LUMA, np.clip(img, 0, 1), axes=(0, 0))
    return 100 * (1 - y[band].mean() / y[ring].mean())


def masks(z, relit: np.ndarray | None) -> np.ndarray:
    rgb = np.transpose(np.clip(z["input"], 0, 1), (1, 2, 0)) * 0.45
    layers = [(z["hole_base"], (1.0, 0.9, 0.1)), (z["hole_own"] & ~z["hole_base"], (1.0, 0.5, 0.0)),
              (z["pieces"], (0.9, 0.1, 0.1))]
    if relit is not None:
        layers.append((relit, (0.1, 0.85, 0.2)))
    for m, c in layers:
        rgb[m] = 0.35 * rgb[m] + 0.65 * np.array(c)
    band = z["band"]
    rgb[band & ~binary_erosion(band)] = (0.0, 1.0, 1.0)
    return rgb


def main() -> int:
    main_dir, branch_dir, out, label = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3], sys.argv[4]
    keys = sys.argv[5:]
    fig, axes = plt.subplots(len(keys), 6, figsize=(22, 3.3 * len(keys)), squeeze=False)
    for row, key in zip(axes, keys, strict=True):
        a, b = np.load(main_dir / f"{key}.npz"), np.load(branch_dir / f"{key}.npz")
        region = binary_dilation(a["vacated"] | a["band"], np.ones((41, 41), bool))
        ys, xs = np.nonzero(region)
        y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
        changed = np.abs(b["output"] - b["input"]).max(0) > 0.004
        relit = changed & ~b["hole_own"] & ~b["pieces"]
        d = [darkening(x["output"], a["band"], a["ring"]) for x in (a, b)] + [
            darkening(a["target"], a["band"], a["ring"])]
        panels = [("input", a["input"]), ("target: exact render without the car", a["target"]),
                  (f"main 7bc89eb: darkening {d[0]:.1f} %", a["output"]),
                  (f"branch ({label}): darkening {d[1]:.1f} %", b["output"]),
                  ("main's hole / joined shadow / pieces", None), ("branch's, + relit faint shadow (green)", None)]
        for ax, (title, img) in zip(row, panels, strict=True):
            if img is not None:
                pic = np.transpose(np.clip(img, 0, 1), (1, 2, 0))
            else:
                pic = masks(a, None) if "main" in title else masks(b, relit)
            ax.imshow(pic[y0:y1, x0:x1], interpolation="nearest")
            ax.set_title(title, fontsize=9)
            ax.axis("off")
        row[0].set_title(f"{key.replace('+', '/')}\ninput (target darkening {d[2]:.1f} %)", fontsize=8)
    fig.suptitle("Counterfactual deletes, photo:rays, w0; cyan outline = true shadow band (ground truth, oracle: "
                 "shown only to judge)", fontsize=11)
    fig.tight_layout()
    fig.savefig(out, dpi=66)
    from PIL import Image  # a 256-colour palette keeps the picture under ~400 KB

    Image.open(out).convert("RGB").quantize(256).save(out, optimize=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
