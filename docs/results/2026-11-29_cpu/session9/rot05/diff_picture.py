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
changed = y["source"] != 0
ys, xs = np.nonzero(changed)
y0, y1 = max(ys.min() - 10, 0), min(ys.max() + 11, changed.shape[0])
x0, x1 = max(xs.min() - 10, 0), min(xs.max() + 11, changed.shape[1])
def rgb(img): return np.ascontiguousarray(img.transpose(1, 2, 0)[y0:y1, x0:x1])
diff = np.clip(np.abs(x["image"].astype(np.int32) - y["image"].astype(np.int32)) * gain, 0, 255).astype(np.uint8)
src = source_picture(torch.from_numpy(y["source"]))[y0:y1, x0:x1]
panels = [("main fc689d8", rgb(x["image"])), ("this branch", rgb(y["image"])), (f"|main - this| x{gain}", rgb(diff)), ("source map (this branch)", np.ascontiguousarray(src))]
rows = []
for label, p in panels:
    p = p.copy()
    cv2.putText(p, label, (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 0), 1, cv2.LINE_AA)
    rows.append(p)
grid = np.concatenate([np.concatenate(rows[:2], 1), np.concatenate(rows[2:], 1)], 0)
cv2.imwrite(out, cv2.cvtColor(grid, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_PNG_COMPRESSION, 9])
print(out, grid.shape, "max abs diff (0-255)", int(np.abs(x["image"].astype(int) - y["image"].astype(int)).max()))
