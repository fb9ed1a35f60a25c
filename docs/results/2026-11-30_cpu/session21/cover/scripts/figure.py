"""Labelled pictures of turned cars: main's, the branch's and their difference, amplified.

    python figure.py real MAIN_DIR BRANCH_DIR OUT.png          # probe.py outputs of the real frame's turns
    python figure.py pairs MAIN.npz BRANCH.npz OUT.png LABEL KEY...   # capture_turns.py outputs: the pairs KEY
                                                                    # (key|angle), titled LABEL (tree, source)

Each row is one edit, cropped to the pixels either code changed (grown by 24 pixels); the difference panel is
``|branch - main|`` (largest channel) times ``AMPLIFY``, and its title counts the pixels that differ.
"""

import io
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

AMPLIFY = 8


def crop_box(mask: np.ndarray, pad: int = 24) -> tuple[slice, slice]:
    ys, xs = np.nonzero(mask)
    h, w = mask.shape
    return slice(max(ys.min() - pad, 0), min(ys.max() + pad + 1, h)), slice(max(xs.min() - pad, 0),
                                                                           min(xs.max() + pad + 1, w))


def draw(rows: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]], out: str) -> None:
    """``rows``: (title, main (H, W, 3) uint8, branch, changed (H, W) bool) per edit."""
    fig, axes = plt.subplots(len(rows), 3, figsize=(12, 2.3 * len(rows)), squeeze=False)
    for ax_row, (title, main, branch, changed) in zip(axes, rows, strict=True):
        sy, sx = crop_box(changed)
        diff = np.abs(branch.astype(np.int32) - main.astype(np.int32)).max(2)
        n = int((diff > 0).sum())
        amp = np.clip(diff * AMPLIFY, 0, 255).astype(np.uint8)
        panels = [(main, f"{title}: main ea2ed39"), (branch, f"{title}: branch s21-cover"),
                  (amp, f"|branch - main| x {AMPLIFY} ({n} px differ, max {int(diff.max())})")]
        for ax, (pic, label) in zip(ax_row, panels, strict=True):
            ax.imshow(pic[sy, sx], cmap="magma" if pic.ndim == 2 else None, vmin=0, vmax=255, interpolation="nearest")
            ax.set_title(label, fontsize=7)
            ax.axis("off")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, dpi=72)
    buffer.seek(0)
    # a palette of 256 colours keeps the file small (each under ~400 KB); the difference panels are 1-channel maps
    Image.open(buffer).convert("RGB").quantize(256).save(out, optimize=True)


def main() -> int:
    mode = sys.argv[1]
    rows = []
    if mode == "real":
        main_dir, branch_dir, out = Path(sys.argv[2]), Path(sys.argv[3]), sys.argv[4]
        for car, name in ((12001, "red car"), (12002, "black car")):
            for angle in (45, 90, 180):
                m = np.load(main_dir / f"{car}_turned_{angle}.npz")
                b = np.load(branch_dir / f"{car}_turned_{angle}.npz")
                changed = (m["source"] != 0) | (b["source"] != 0)
                rows.append((f"real frame, {name} turned {angle}", m["edited"], b["edited"], changed))
    else:
        m, b, out = np.load(sys.argv[2]), np.load(sys.argv[3]), sys.argv[4]
        index = {str(k): i for i, k in enumerate(m["keys"])}
        bindex = {str(k): i for i, k in enumerate(b["keys"])}
        for key in sys.argv[6:]:
            i, j = index[key], bindex[key]
            pm, pb = m["pictures"][i].transpose(1, 2, 0), b["pictures"][j].transpose(1, 2, 0)
            name, angle = key.split("|")
            world, variation, car = name.split()[0].split("/")
            rows.append((f"{sys.argv[5]} {world} {variation} {car} turned {float(angle):g}", pm, pb,
                         m["masks"][i] > 0))
    draw(rows, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
