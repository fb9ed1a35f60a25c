# ruff: noqa: E402, E501, E701, E702
"""pics_t1_sheet.py OUT.png TREE_SRC:IDX[:title] ...: Table 1 before/after sheet from pics/<TREE_SRC>_{off,always,gated}.npz;
panels: input, target (edit region outlined in red), ray_haze off, always on (session start), gated (final), with
each one's 3D-SDN PSNR on the edit region; crops around the edit region, 3x."""
import sys

import numpy as np
from PIL import Image, ImageDraw

D = "/tmp/s7data/haze/pics"
strips = []
for spec in sys.argv[2:]:
    ts, idx, *title = spec.split(":")
    z = {t: np.load(f"{D}/{ts}_{t}.npz") for t in ("off", "always", "gated")}
    reg = z["gated"][f"{idx}_region"].astype(bool)
    if reg.ndim == 3: reg = reg.any(0)
    ys, xs = np.nonzero(reg); H, W = reg.shape; pad = 16
    y0, y1, x0, x1 = max(0, ys.min() - pad), min(H, ys.max() + pad + 1), max(0, xs.min() - pad), min(W, xs.max() + pad + 1)
    tgt = z["gated"][f"{idx}_target"].copy()
    edge = reg & ~np.pad(reg, 1)[2:, 1:-1] | reg & ~np.pad(reg, 1)[:-2, 1:-1] | reg & ~np.pad(reg, 1)[1:-1, 2:] | reg & ~np.pad(reg, 1)[1:-1, :-2]
    tgt[edge] = [255, 0, 0]
    panels = [("input", z["gated"][f"{idx}_source"]), ("target (region red)", tgt)]
    for t, name in (("off", "ray_haze off"), ("always", "always on (start)"), ("gated", "gated (final)")):
        panels.append((f"{name} {float(z[t][f'{idx}_psnr']):.1f} dB", z[t][f"{idx}_photo"]))
    s = 6 if (x1 - x0) < 70 else 3; tiles = []
    for name, a in panels:
        t = Image.fromarray(np.ascontiguousarray(a[y0:y1, x0:x1])).resize(((x1 - x0) * s, (y1 - y0) * s), Image.NEAREST)
        c = Image.new("RGB", (max(t.width, 110), t.height + 14), "white"); c.paste(t, (0, 14)); ImageDraw.Draw(c).text((2, 1), name, fill="black"); tiles.append(c)
    w = sum(t.width + 4 for t in tiles); h = max(t.height for t in tiles) + 14
    strip = Image.new("RGB", (w, h), "white"); ImageDraw.Draw(strip).text((2, 1), f"{ts} entry {idx} {' '.join(title)}", fill="black")
    x = 0
    for t in tiles: strip.paste(t, (x, 14)); x += t.width + 4
    strips.append(strip)
sheet = Image.new("RGB", (max(s.width for s in strips), sum(s.height for s in strips)), "white"); y = 0
for s_ in strips: sheet.paste(s_, (0, y)); y += s_.height
sheet.save(sys.argv[1], optimize=True); print(sys.argv[1], sheet.size)
