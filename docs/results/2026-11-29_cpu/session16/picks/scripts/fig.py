# ruff: noqa: E501, E701, E702
"""fig.py OUT.png TREE MAIN_DUMP BRANCH_DUMP IDX[,IDX...]: one row per Table 1 entry IDX (dbench.py's npz of main's
run and of the branch's), cropped to the edited region and both codes' picks (10 px margin), upscaled 4x. Panels:
source with each operation's `from` point (yellow cross), main's 3D-SDN pick (red outline) and the branch's (green
outline); target; 2D paste; 3D-SDN on main; 3D-SDN on the branch. Titles: PSNR of 'all' against the target."""
import os
import sys

import numpy as np
from PIL import Image, ImageDraw

from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation

out, tree, mdump, bdump, idx = sys.argv[1:6]
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
S, M, H = 4, 10, 16


def outline(m):
    m = m.astype(bool); e = m.copy()
    e[1:] &= m[:-1]; e[:-1] &= m[1:]; e[:, 1:] &= m[:, :-1]; e[:, :-1] &= m[:, 1:]
    return m & ~e


def psnr(img, z):
    m = z["region"].astype(bool); e = ((img.astype(float) - z["target"].astype(float)) ** 2).mean(-1)[m].mean()
    return 10 * np.log10(255 ** 2 / e)


rows = []
for i in [int(x) for x in idx.split(",")]:
    zm, zb = np.load(os.path.join(mdump, f"{i:04d}.npz")), np.load(os.path.join(bdump, f"{i:04d}.npz"))
    pm = np.isin(zm["proposals"], zm["picks"]); pb = np.isin(zb["proposals"], zb["picks"])
    pts = [scale_operation(op, (1242, 375), (312, 96)).from_uv for op in entries[i].operations]
    ys, xs = np.nonzero(zm["region"].astype(bool) | pm | pb)
    y0, y1, x0, x1 = max(ys.min() - M, 0), min(ys.max() + M + 1, 96), max(xs.min() - M, 0), min(xs.max() + M + 1, 312)
    src = zm["source"].copy()
    src[outline(pm)] = (255, 40, 40); src[outline(pb)] = (40, 255, 40)
    panels = [("source: from +, main pick red, branch green", src), ("target", zm["target"]),
              (f"2D paste {psnr(zm['d2'], zm):.2f} dB", zm["d2"]), (f"3D-SDN main {psnr(zm['sdn'], zm):.2f}", zm["sdn"]),
              (f"3D-SDN branch {psnr(zb['sdn'], zb):.2f}", zb["sdn"])]
    tiles = []
    for k, (title, img) in enumerate(panels):
        crop = np.kron(img[y0:y1, x0:x1].astype(np.uint8), np.ones((S, S, 1), np.uint8))
        tile = Image.new("RGB", (max(crop.shape[1], 250), crop.shape[0] + H), (255, 255, 255))
        tile.paste(Image.fromarray(crop), (0, H))
        d = ImageDraw.Draw(tile); d.text((2, 2), title, fill=(0, 0, 0))
        if k == 0:
            for u, v in pts:
                cu, cv = (u - x0 + 0.5) * S, (v - y0 + 0.5) * S + H
                d.line([(cu - 6, cv), (cu + 6, cv)], fill=(255, 230, 0), width=2); d.line([(cu, cv - 6), (cu, cv + 6)], fill=(255, 230, 0), width=2)
        tiles.append(tile)
    w = sum(t.width for t in tiles) + 4 * len(tiles); h = max(t.height for t in tiles)
    row = Image.new("RGB", (w, h + H), (255, 255, 255)); x = 0
    ImageDraw.Draw(row).text((2, 2), f"entry {i} ({zm['key']}, {zm['kind']}); main picks {zm['picks'].tolist()}, branch picks {zb['picks'].tolist()}", fill=(0, 0, 120))
    for t in tiles: row.paste(t, (x, H)); x += t.width + 4
    rows.append(row)
W = max(r.width for r in rows); fig = Image.new("RGB", (W, sum(r.height for r in rows)), (255, 255, 255)); y = 0
for r in rows: fig.paste(r, (0, y)); y += r.height
fig.save(out)
