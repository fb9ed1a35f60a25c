"""synthetic_figure.py MAIN.pt BRANCH.pt OUT.png TITLE: one counterfactual delete captured by capture.py (this folder;
CAPTURE=FILE KEYS=KEY, sdn3d-bench's arguments) with main's code and the branch's, cropped around the pixels where the
two pictures differ (40 pixels around, three times the size): the input, the truth (the exact render without the
car), main's picture, the branch's and the pixels that differ (magenta), every panel titled; where they differ in
several places, around the largest (the differing pixels grown by 15, 8-connected)."""

from __future__ import annotations

import sys

import numpy as np
import torch
from PIL import Image, ImageDraw


def picture(t: torch.Tensor) -> np.ndarray:
    t = t.float()
    if float(t.max()) > 1.5:
        t = t / 255
    return (t.clamp(0, 1).permute(1, 2, 0).numpy() * 255 + 0.5).astype(np.uint8)


def main() -> int:
    m, b = torch.load(sys.argv[1], weights_only=False), torch.load(sys.argv[2], weights_only=False)
    out, title = sys.argv[3], sys.argv[4]
    key = next(iter(m))
    pm, pb = picture(m[key]["pics"][0]), picture(b[key]["pics"][0])
    diff = np.abs(pm.astype(int) - pb).sum(2) > 0
    import cv2

    grown = cv2.dilate(diff.astype(np.uint8), np.ones((31, 31), np.uint8))
    _, groups, stats, _ = cv2.connectedComponentsWithStats(grown)
    ys, xs = np.nonzero(diff & (groups == 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))))
    y0, y1 = max(int(ys.min()) - 40, 0), min(int(ys.max()) + 41, pm.shape[0])
    x0, x1 = max(int(xs.min()) - 40, 0), min(int(xs.max()) + 41, pm.shape[1])
    changed = np.zeros_like(pm)
    changed[diff] = (255, 0, 255)
    panels = [("input", picture(m[key]["image"])), ("truth (exact render without the car)", picture(m[key]["target"])),
              ("main (ea2ed39)", pm), ("branch (4552a27)", pb), (f"pixels that differ ({int(diff.sum())})", changed)]
    tiles = []
    for name, pic in panels:
        crop = Image.fromarray(pic[y0:y1, x0:x1]).resize(((x1 - x0) * 3, (y1 - y0) * 3), Image.NEAREST)
        tile = Image.new("RGB", (crop.width, crop.height + 14), "white")
        tile.paste(crop, (0, 14))
        ImageDraw.Draw(tile).text((2, 1), name, fill="black")
        tiles.append(tile)
    sheet = Image.new("RGB", (sum(t.width + 6 for t in tiles), tiles[0].height + 16), "white")
    ImageDraw.Draw(sheet).text((2, 1), f"{title}: {key}", fill="black")
    x = 0
    for t in tiles:
        sheet.paste(t, (x, 16))
        x += t.width + 6
    sheet.save(out)
    print(out, sheet.size)
    return 0


if __name__ == "__main__":
    sys.exit(main())
