"""Where 3D-SDN loses to 2D in a bench example grid: python errmap.py GRID.png U V OUT.png"""
import sys

import numpy as np
from PIL import Image

img = np.asarray(Image.open(sys.argv[1]).convert("RGB")).astype(float) / 255
band = img.shape[0] - 96
p = [img[band:, k * 316:k * 316 + 312] for k in range(5)]
src, tgt, d3, d2 = p[0], p[1], p[2], p[3]
e3 = np.abs(d3 - tgt).mean(-1)
e2 = np.abs(d2 - tgt).mean(-1)
u, v = float(sys.argv[2]) * 312 / 1242, float(sys.argv[3]) * 96 / 375
a, b, c, d = int(max(u - 24, 0)), int(min(u + 24, 312)), int(max(v - 20, 0)), int(min(v + 10, 96))
diff = e3 - e2
vis = np.zeros((96, 312, 3))
vis[..., 0] = np.clip(diff * 4, 0, 1)
vis[..., 1] = np.clip(-diff * 4, 0, 1)
tiles = [src, tgt, d3, d2, vis]
out = np.concatenate([np.pad(t[c:d, a:b], ((0, 0), (0, 1), (0, 0)), constant_values=1) for t in tiles], 1)
big = (out.shape[1] * 6, out.shape[0] * 6)
Image.fromarray((out * 255).astype(np.uint8)).resize(big, Image.NEAREST).save(sys.argv[4])
print("sum |e3|-|e2| in window", diff[c:d, a:b].sum(), "whole", diff.sum())
