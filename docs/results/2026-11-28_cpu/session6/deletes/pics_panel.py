# ruff: noqa: E401, I001, B023, E402, E501, E701, E702
"""Labelled rows (input | target | variants...) cropped around the hole, from a diag_pics.py .pics.pt file.
python pics_panel.py PICS.pt OUT.png NAME=LABEL,NAME=LABEL,..."""
import sys, numpy as np, torch
from PIL import Image
from sdn3d.visualize import titled_row
P = torch.load(sys.argv[1], weights_only=False); out = sys.argv[2]
names = [x.split("=", 1) for x in sys.argv[3].split(",")]
rows = []
for key, d in P.items():
    hole = d["hole"]; ys, xs = hole.nonzero(as_tuple=True)
    H, W = hole.shape
    y0, y1 = max(int(ys.min()) - 30, 0), min(int(ys.max()) + 30, H)
    x0, x1 = max(int(xs.min()) - 60, 0), min(int(xs.max()) + 60, W)
    def u8(t): return (t.clamp(0, 1).permute(1, 2, 0).numpy()[y0:y1, x0:x1] * 255 + 0.5).astype(np.uint8)
    def ps(t):
        return 10 * np.log10(1 / max(float(((t - d['target'])[:, hole] ** 2).mean()), 1e-6))
    panels = [(f"input {key}", u8(d["input"])), ("target", u8(d["target"]))]
    panels += [(f"{lab} {ps(d[n]):.1f} dB", u8(d[n])) for n, lab in names]
    rows.append(titled_row(panels))
width = max(r.shape[1] for r in rows)
grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
Image.fromarray(grid).quantize(256, dither=Image.Dither.NONE).save(out, optimize=True)
print(out, grid.shape)
