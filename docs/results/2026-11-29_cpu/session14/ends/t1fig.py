# ruff: noqa: E501
"""t1fig.py OUT.png BASE_DUMP NEW_DUMP RESULTS_BASE RESULTS_NEW ENTRY[,ENTRY...]: Table 1 entries from session 11
semrain's dbench.py dumps (photo row): per entry a row cropped to its 'all' region (plus 6 px) and enlarged: source,
target, main's 3D-SDN, this branch's 3D-SDN, the 2D paste, each titled, with both 3D-SDN PSNR (all) in the row title."""

from __future__ import annotations

import json
import sys

import numpy as np
from PIL import Image, ImageDraw


def psnr(results: str, idx: int) -> tuple[float, float]:
    r = json.load(open(f"{results}/results.json"))
    e = [e for e in list(r["entries"].values())[0] if e["index"] == idx][0]
    m = e["metrics"]["photo"]
    return m["3d-sdn"]["all"]["psnr"], m["2d"]["all"]["psnr"]


def main() -> None:
    out, base, new, rb, rn, entries = sys.argv[1:7]
    rows = []
    for idx in [int(x) for x in entries.split(",")]:
        b, n = np.load(f"{base}/{idx:04d}.npz"), np.load(f"{new}/{idx:04d}.npz")
        ys, xs = np.nonzero(b["region"])
        y0, y1, x0, x1 = max(0, ys.min() - 6), ys.max() + 7, max(0, xs.min() - 6), xs.max() + 7
        scale = max(2, min(6, 150 // (y1 - y0)))
        (pb, p2), (pn, _) = psnr(rb, idx), psnr(rn, idx)
        panels = [("source", b["source"]), ("target", b["target"]), (f"main 3D-SDN {pb:.2f} dB", b["sdn"]),
                  (f"branch 3D-SDN {pn:.2f} dB", n["sdn"]), (f"2D paste {p2:.2f} dB", b["d2"])]
        tiles = []
        for title, img in panels:
            c = Image.fromarray(np.ascontiguousarray(img[y0:y1, x0:x1])).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST)
            t = Image.new("RGB", (max(c.width, 130), c.height + 14), "white")
            t.paste(c, (0, 14))
            ImageDraw.Draw(t).text((2, 1), title, fill=(0, 0, 160))
            tiles.append(t)
        row = Image.new("RGB", (sum(t.width + 4 for t in tiles), max(t.height for t in tiles) + 14), "white")
        ImageDraw.Draw(row).text((2, 1), f"entry {idx} ({b['key']}, {b['kind']})", fill=(0, 0, 0))
        x = 0
        for t in tiles:
            row.paste(t, (x, 14))
            x += t.width + 4
        rows.append(row)
    canvas = Image.new("RGB", (max(r.width for r in rows), sum(r.height for r in rows)), "white")
    y = 0
    for r in rows:
        canvas.paste(r, (0, y))
        y += r.height
    canvas.save(out)


if __name__ == "__main__":
    main()
