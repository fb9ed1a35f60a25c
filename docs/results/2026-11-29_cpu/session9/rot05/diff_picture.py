# ruff: noqa: E402, E501, E701, E702
"""diff_picture.py MAIN_DIR THIS_DIR NAME OUT.png [GAIN]: one replayed edit (replay_photo.py) drawn by main and by this
branch, cropped to what the edit changed: main's picture, this branch's, their absolute difference times GAIN (default 50), and this
branch's source map (photo_source colours of sdn3d.editing.photo.settings.source_picture)."""
import sys

import cv2
import numpy as np
import torch

from sdn3d.editing.photo.settings import source_picture

a, b, name, out = sys.argv[1:5]
gain = int(sys.argv[5]) if len(sys.argv) > 5 else 50
x, y = np.load(f"{a}/{name}.npz"), np.load(f"{b}/{name}.npz")
def u8(img): return img if img.dtype == np.uint8 else (np.clip(img, 0, 1) * 255).round().astype(np.uint8)  # float pictures (the captured Table 1 calls)
xi, yi = u8(x["image"]), u8(y["image"])
changed = y["source"] != 0
ys, xs = np.nonzero(changed)
y0, y1 = max(ys.min() - 10, 0), min(ys.max() + 11, changed.shape[0])
x0, x1 = max(xs.min() - 10, 0), min(xs.max() + 11, changed.shape[1])
def rgb(img): return np.ascontiguousarray(img.transpose(1, 2, 0)[y0:y1, x0:x1])
fx, fy = (x["image"].astype(np.float64), y["image"].astype(np.float64)) if x["image"].dtype == np.uint8 else (x["image"] * 255.0, y["image"] * 255.0)
diff = np.clip(np.abs(fx - fy) * gain, 0, 255).astype(np.uint8)
src = source_picture(torch.from_numpy(y["source"]))[y0:y1, x0:x1]
panels = [("main fc689d8", rgb(xi)), ("this branch", rgb(yi)), (f"|main - this| x{gain}", rgb(diff)), ("source map (this branch)", np.ascontiguousarray(src))]
rows = []
up = max(1, 1200 // (2 * panels[0][1].shape[1]))  # small pictures (Table 1's) enlarged, nearest pixel
for label, p in panels:
    p = np.ascontiguousarray(np.repeat(np.repeat(p, up, 0), up, 1))
    cv2.putText(p, label, (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 0), 1, cv2.LINE_AA)
    rows.append(p)
grid = np.concatenate([np.concatenate(rows[:2], 1), np.concatenate(rows[2:], 1)], 0)
cv2.imwrite(out, cv2.cvtColor(grid, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_PNG_COMPRESSION, 9])
print(out, grid.shape, "max abs diff (0-255)", round(float(np.abs(fx - fy).max()), 2))
