"""synthetic_figure.py OUT.png TITLE MAIN.pt BRANCH.pt [TITLE MAIN.pt BRANCH.pt ...]: per captured delete (cap.sh's
/tmp/s21data/island/cap_TAG.pt, one pair each) a row: input, target (the render without the car), main's and the
branch's pictures and the pixels they draw differently (white), cropped to the scored region (vacated plus shadow
band) grown by 24 pixels, at three times the size; every panel titled, each row headed by TITLE and the pair.

    PYTHONPATH=src python synthetic_figure.py OUT.png "tuning cf31, predicted" \\
        /tmp/s21data/island/cap_t31main.pt /tmp/s21data/island/cap_t31br.pt
"""

from __future__ import annotations

import sys

import numpy as np
import torch
from PIL import Image, ImageDraw


def u8(t: torch.Tensor) -> np.ndarray:
    return (t.clamp(0, 1) * 255).byte().permute(1, 2, 0).numpy()


def panel(picture: np.ndarray, title: str, scale: int = 3) -> Image.Image:
    img = Image.fromarray(picture).resize((picture.shape[1] * scale, picture.shape[0] * scale), Image.NEAREST)
    out = Image.new("RGB", (img.width, img.height + 14), "white")
    out.paste(img, (0, 14))
    ImageDraw.Draw(out).text((2, 1), title, fill="black")
    return out


def main() -> int:
    target, args = sys.argv[1], sys.argv[2:]
    rows = []
    for i in range(0, len(args), 3):
        title, main_pt, branch_pt = args[i:i + 3]
        theirs = torch.load(main_pt, weights_only=False)
        ours = torch.load(branch_pt, weights_only=False)
        key = next(iter(theirs))
        e, f = theirs[key], ours[key]
        scored = (e["masks"]["vacated"] | e["masks"]["shadow"]).numpy()
        ys, xs = np.nonzero(scored)
        h, w = scored.shape
        y0, y1, x0, x1 = max(ys.min() - 24, 0), min(ys.max() + 25, h), max(xs.min() - 24, 0), min(xs.max() + 25, w)
        diff = ((e["pics"][0] - f["pics"][0]).abs().sum(0) > 0).numpy()
        dm = np.zeros((h, w, 3), np.uint8)
        dm[diff] = 255
        crop = (slice(y0, y1), slice(x0, x1))
        heading = Image.new("RGB", (600, 14), "white")
        ImageDraw.Draw(heading).text((2, 1), f"{title} ({key})", fill="black")
        rows.append([heading])
        rows.append([panel(u8(e["image"])[crop], "input"), panel(u8(e["target"])[crop], "target (no car)"),
                     panel(u8(e["pics"][0])[crop], "main (debaff5)"), panel(u8(f["pics"][0])[crop], "branch (f67b9ba)"),
                     panel(dm[crop], f"pixels drawn differently ({int(diff.sum())})")])
    width = max(sum(p.width + 6 for p in r) for r in rows)
    sheet = Image.new("RGB", (width, sum(max(p.height for p in r) + 6 for r in rows)), "white")
    y = 0
    for r in rows:
        x = 0
        for p in r:
            sheet.paste(p, (x, y))
            x += p.width + 6
        y += max(p.height for p in r) + 6
    sheet.save(target, optimize=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
