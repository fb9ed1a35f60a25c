# ruff: noqa: E501, E701, E702
"""worstfig.py OUT.png POSES.json DUMP_DIR N [DUMP_DIR_NEW]: the N entries of one run with the lowest 3D-SDN minus
2D paste PSNR all (poses.py's json), one row each, cropped to the edited region, the picked proposal and the car
(12 px margin) and upscaled 4x. Panels: source (picked proposal red, ground-truth car green: oracle, for scoring);
target; 3D-SDN; 2D paste; |3D-SDN - target|; |2D - target| (grey levels, 'all' region outlined yellow);
[3D-SDN of DUMP_DIR_NEW and its |error|, titled NEWLABEL (environment; 'new')]. The row's caption: entry, kind, dB, and per modify operation the turn, the
zoom and the fitted pose against the truth's (yaw error, template fitted/true, distance ratio, proposal IoU)."""
import json
import os
import sys

import numpy as np
from PIL import Image, ImageDraw

out, poses, dump, n = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
new = sys.argv[5] if len(sys.argv) > 5 else None
S = 4


def outline(m):
    m = m.astype(bool); e = m.copy()
    e[1:] &= m[:-1]; e[:-1] &= m[1:]; e[:, 1:] &= m[:, :-1]; e[:, :-1] &= m[:, 1:]
    return m & ~e


def up(a):
    return np.kron(a, np.ones((S, S, 1), a.dtype))


def err(img, z):
    e = np.abs(img.astype(float) - z["target"].astype(float)).mean(-1)
    g = np.clip(e * 2.5, 0, 255).astype(np.uint8)
    rgb = np.stack([g] * 3, -1); rgb[outline(z["region"])] = (230, 200, 0)
    return rgb


def psnr(img, z):
    m = z["region"].astype(bool); e = ((img.astype(float) - z["target"].astype(float)) ** 2).mean(-1)[m].mean()
    return 10 * np.log10(255 ** 2 / e)


rows = sorted(json.load(open(poses)), key=lambda r: r["d_all"])[:n]
tiles_rows = []
for r in rows:
    z = np.load(f"{dump}/{r['index']:04d}.npz")
    inp = z["source"].copy()
    P = np.isin(z["proposals"], z["picks"]) & (z["proposals"] != 0)
    G = np.isin(z["src_inst"], z["gt_ids"])
    inp[outline(G)] = (0, 255, 0); inp[outline(P)] = (255, 0, 0)
    panels = [(inp, "source: pick red, truth green"), (z["target"], "target"), (z["sdn"], f"3D-SDN {psnr(z['sdn'], z):.2f} dB"),
              (z["d2"], f"2D paste {psnr(z['d2'], z):.2f} dB"), (err(z["sdn"], z), "|3D-SDN - target|"), (err(z["d2"], z), "|2D - target|")]
    if new:
        zn = np.load(f"{new}/{r['index']:04d}.npz")
        label = os.environ.get("NEWLABEL", "new")
        panels += [(zn["sdn"], f"3D-SDN {label} {psnr(zn['sdn'], zn):.2f} dB"), (err(zn["sdn"], zn), f"|{label} - target|")]
    ys, xs = np.nonzero(z["region"].astype(bool) | P | G)
    y0, y1 = max(ys.min() - 12, 0), min(ys.max() + 13, inp.shape[0]); x0, x1 = max(xs.min() - 12, 0), min(xs.max() + 13, inp.shape[1])
    x1 = max(x1, min(x0 + 40, inp.shape[1]))
    tiles = []
    for img, title in panels:
        im = Image.fromarray(up(np.ascontiguousarray(img[y0:y1, x0:x1])))
        canvas = Image.new("RGB", (max(im.width, 6 * len(title) + 4), im.height + 14), "white"); canvas.paste(im, (0, 14))
        ImageDraw.Draw(canvas).text((2, 1), title, fill="black"); tiles.append(canvas)
    ops = "; ".join(o["type"] + (f" turn {o['turn_deg']:+.0f} zoom {o['zoom']:.2f}" if o["type"] == "modify" else "")
                    + (f" | fit vs truth: yaw err {o['yaw_err']:+.0f}, template {o['tpl'][0]}/{o['tpl'][1]}, dist x{o['dist_ratio']:.2f}, len x{o['len_ratio']:.2f}, mask IoU {o['mask_iou']:.2f}" if "yaw_err" in o else "")
                    for o in r["ops"])
    cap = f"#{r['index']} {r['key']} {r['kind']}: 3D-2D {r['d_all']:+.2f} dB (objects {r['d_obj']:+.2f}) -- {ops}"
    w = sum(t.width for t in tiles) + 4 * len(tiles)
    row = Image.new("RGB", (max(w, 6 * len(cap) + 4), tiles[0].height + 18), "white")
    ImageDraw.Draw(row).text((2, 2), cap, fill=(0, 0, 160))
    x = 0
    for tl in tiles: row.paste(tl, (x, 16)); x += tl.width + 4
    tiles_rows.append(row)
    if os.environ.get("ROWDIR"): row.save(f"{os.environ['ROWDIR']}/{len(tiles_rows):02d}_{r['index']:04d}.png")
fig = Image.new("RGB", (max(r.width for r in tiles_rows), sum(r.height for r in tiles_rows)), "white")
y = 0
for r in tiles_rows: fig.paste(r, (0, y)); y += r.height
fig.save(out)
print(out, fig.size)
