# ruff: noqa: E402, E501, E701, E702
"""beltseg.py DIR...: the belt step (scripts/belt.py) of diag_real.py runs per 50-px stretch of the red car, with the
mean luma of the glass pixel above and the body pixel below (needs DIR/diag_maps.npz)."""
import sys

import numpy as np
from PIL import Image

for d in sys.argv[1:]:
    L = np.asarray(Image.open(f"{d}/edited.png").convert("RGB")).astype(float) @ np.array([0.299, 0.587, 0.114])
    mp = np.load(f"{d}/diag_maps.npz"); h, w = L.shape
    parts = mp["parts"].reshape(h, w); src = mp["source"].reshape(h, w)
    mine = np.zeros(h*w, bool); mine[mp["pix"][mp["mesh"] == 0]] = True
    new = mine.reshape(h, w) & np.isin(src, [3, 7, 8, 11])
    g = new & (parts == 1); b = new & (parts == 0)
    seg = {}
    for x in range(w):
        ys = np.nonzero(g[:-1, x] & b[1:, x])[0]
        if len(ys):
            y = ys[0]; k = (x - 460) // 50
            seg.setdefault(k, []).append((abs(L[y+1, x] - L[y, x]), L[y, x], L[y+1, x]))
    print(d.ljust(18), ' '.join(f"{460+50*k}:{np.mean([s[0] for s in v]):5.1f}({np.mean([s[1] for s in v]):3.0f}/{np.mean([s[2] for s in v]):3.0f})" for k, v in sorted(seg.items())))
