"""Labelled panels of Table 1 entries from two dbench.py dumps (predicted and oracle runs of one code).

python panels.py PRED_RUN GT_RUN OUT.png INDEX... [--other OTHER_PRED_RUN LABEL]
Rows: one per entry; panels: input, target, 2D (predicted proposal), 3D-SDN (predicted) [, 3D-SDN (predicted) of
OTHER], 3D-SDN (ground-truth masks, oracle), the picked proposal (red) over the car's ground-truth mask (green) with the
pixels 3D-SDN drew (blue outline), cropped around the entry's 'all' region, 3x."""
import json
import sys

import numpy as np
from PIL import Image, ImageDraw

SCALE = 3
DRAWN = (1, 2, 3, 5, 7, 8, 9, 11)


def psnr(run, i):
    res = json.load(open(f"{run}/results.json"))
    entries = next(iter(res["entries"].values()))
    e = {x["index"]: x for x in entries}[i]["metrics"]["photo"]
    return e["3d-sdn"]["all"]["psnr"], e["2d"]["all"]["psnr"]


def crop_box(region, h, w, pad=12):
    ys, xs = np.nonzero(region)
    if len(ys) == 0:
        return 0, h, 0, w
    y0, y1 = max(ys.min() - pad, 0), min(ys.max() + pad + 1, h)
    x0, x1 = max(xs.min() - pad, 0), min(xs.max() + pad + 1, w)
    if x1 - x0 < 60:
        c = (x0 + x1) // 2
        x0, x1 = max(c - 30, 0), min(c + 30, w)
    return y0, y1, x0, x1


def panel(img, box, title):
    y0, y1, x0, x1 = box
    im = Image.fromarray(np.ascontiguousarray(img[y0:y1, x0:x1])).resize(((x1 - x0) * SCALE, (y1 - y0) * SCALE),
                                                                        Image.NEAREST)
    out = Image.new("RGB", (im.width, im.height + 28), "white")
    out.paste(im, (0, 28))
    d = ImageDraw.Draw(out)
    for k, line in enumerate(title.split("\n")):
        d.text((2, 1 + 13 * k), line, fill="black")
    return out


def main():
    args = sys.argv[1:]
    other = None
    if "--other" in args:
        k = args.index("--other")
        other = (args[k + 1], args[k + 2])
        args = args[:k] + args[k + 3:]
    pred, gt, out = args[:3]
    rows = []
    for i in map(int, args[3:]):
        zp = np.load(f"{pred}.dump/{i:04d}.npz", allow_pickle=True)
        zg = np.load(f"{gt}.dump/{i:04d}.npz", allow_pickle=True)
        h, w = zp["region"].shape
        box = crop_box(zp["region"] | zg["region"], h, w)
        sp, dp = psnr(pred, i)
        sg, dg = psnr(gt, i)
        gid = int(zp["gt_ids"][0])
        pick = int(zp["picks"][0]) if len(zp["picks"]) else -1
        ov = (zp["source"] * 0.4).astype(np.uint8)
        ov[zp["src_inst"] == gid, 1] = 220
        ov[zp["proposals"] == pick, 0] = 230
        drawn = np.isin(zp["code"], DRAWN)
        edge = drawn & ~(np.roll(drawn, 1, 0) & np.roll(drawn, -1, 0) & np.roll(drawn, 1, 1) & np.roll(drawn, -1, 1))
        ov[edge] = (80, 140, 255)
        ps = [panel(zp["source"], box, f"#{i} input\n{zp['key']} {zp['kind']}"), panel(zp["target"], box, "target"),
              panel(zp["d2"], box, f"2D paste (predicted)\n{dp:.2f} dB"),
              panel(zp["sdn"], box, f"3D-SDN main (predicted)\n{sp:.2f} dB")]
        if other:
            zo = np.load(f"{other[0]}.dump/{i:04d}.npz", allow_pickle=True)
            so, _ = psnr(other[0], i)
            ps.append(panel(zo["sdn"], box, f"3D-SDN {other[1]} (predicted)\n{so:.2f} dB"))
        ps += [panel(zg["sdn"], box, f"3D-SDN main (gt masks, oracle)\n{sg:.2f} dB (2D {dg:.2f})"),
               panel(ov, box, "proposal red, gt car green\nmain's drawn pixels blue")]
        row = Image.new("RGB", (sum(p.width for p in ps) + 4 * len(ps), max(p.height for p in ps) + 4), "white")
        x = 0
        for p in ps:
            row.paste(p, (x, 0))
            x += p.width + 4
        rows.append(row)
    sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height for r in rows)), "white")
    y = 0
    for r in rows:
        sheet.paste(r, (0, y))
        y += r.height
    sheet.save(out)


if __name__ == "__main__":
    main()
