# ruff: noqa: E501, E701, E702
"""fig.py OUT.png BEFORE_DUMP AFTER_DUMP FILE...: one row per entry (dbench.py dumps of two runs of the same tree;
AFTER_DUMP '-': main's panels alone):
input with the picked proposal (red outline) and the ground-truth car (oracle, green outline); target; 2D paste;
3D-SDN before; 3D-SDN after; per-pixel error difference |3D-SDN - target| - |2D - target| (before, after; red: 3D-SDN
worse, blue: better) with the 'all' region outlined in yellow. Panels cropped to the region, the proposal and the car
(16 px margin) and upscaled 4x, each titled."""
import sys

import numpy as np
from PIL import Image, ImageDraw

out, before, after, files = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
S = 4


def outline(m):
    m = m.astype(bool); e = m.copy()
    e[1:] &= m[:-1]; e[:-1] &= m[1:]; e[:, 1:] &= m[:, :-1]; e[:, :-1] &= m[:, 1:]
    return m & ~e


def up(a):
    return np.kron(a, np.ones((S, S, 1), a.dtype)) if a.ndim == 3 else np.kron(a, np.ones((S, S), a.dtype))


def diffmap(z):
    t = z["target"].astype(float)
    d = np.abs(z["sdn"] - t).mean(-1) - np.abs(z["d2"] - t).mean(-1)
    rgb = np.full(d.shape + (3,), 255.0)
    pos = np.clip(d / 80, 0, 1); neg = np.clip(-d / 80, 0, 1)
    rgb[..., 1] -= 255 * (pos + neg); rgb[..., 2] -= 255 * pos; rgb[..., 0] -= 255 * neg
    rgb = rgb.clip(0, 255).astype(np.uint8)
    rgb[outline(z["region"])] = (230, 200, 0)
    return rgb


rows = []
for f in files:
    zb = np.load(f"{before}/{f}")
    za = zb if after == "-" else np.load(f"{after}/{f}")
    inp = zb["source"].copy()
    P = np.isin(zb["proposals"], zb["picks"]) & (zb["proposals"] != 0)
    G = np.isin(zb["src_inst"], zb["gt_ids"])
    inp[outline(G)] = (0, 255, 0); inp[outline(P)] = (255, 0, 0)
    def ps(img, z):
        m = z["region"].astype(bool); e = ((img.astype(float) - z["target"].astype(float)) ** 2).mean(-1)[m].mean()
        return 10 * np.log10(255 ** 2 / e)
    panels = [(inp, f"input {zb['key']} {zb['kind']}: proposal red, truth green"), (zb["target"], "target"),
              (zb["d2"], f"2D paste {ps(zb['d2'], zb):.2f} dB"), (zb["sdn"], f"3D-SDN main {ps(zb['sdn'], zb):.2f} dB"),
              (za["sdn"], f"3D-SDN new {ps(za['sdn'], za):.2f} dB"), (diffmap(zb), "err 3D-2D, main (red: 3D worse)"),
              (diffmap(za), "err 3D-2D, new")]
    if after == "-":
        panels = panels[:4] + panels[5:6]
        panels[0] = (inp, f"input {str(zb['key']).split(' ')[0]} {zb['kind']}")
        panels[3] = (zb["sdn"], f"3D-SDN {ps(zb['sdn'], zb):.2f} dB")
        panels[4] = (diffmap(zb), "error 3D minus 2D")
    ys, xs = np.nonzero(zb["region"].astype(bool) | P | G)
    y0, y1 = max(ys.min() - 16, 0), min(ys.max() + 17, inp.shape[0]); x0, x1 = max(xs.min() - 16, 0), min(xs.max() + 17, inp.shape[1])
    x1 = max(x1, min(x0 + 64, inp.shape[1]))
    tiles = []
    for img, title in panels:
        im = Image.fromarray(up(np.ascontiguousarray(img[y0:y1, x0:x1])))
        title = title if len(title) * 6 < im.width else title[: im.width // 6]
        canvas = Image.new("RGB", (im.width, im.height + 14), "white"); canvas.paste(im, (0, 14))
        ImageDraw.Draw(canvas).text((2, 1), title, fill="black"); tiles.append(canvas)
    row = Image.new("RGB", (sum(t.width for t in tiles) + 4 * len(tiles), tiles[0].height + 4), "white")
    x = 0
    for tl in tiles: row.paste(tl, (x, 2)); x += tl.width + 4
    rows.append(row)
fig = Image.new("RGB", (max(r.width for r in rows), sum(r.height for r in rows)), "white")
y = 0
for r in rows: fig.paste(r, (0, y)); y += r.height
fig.save(out)
