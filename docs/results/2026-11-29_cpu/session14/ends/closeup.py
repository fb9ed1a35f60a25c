# ruff: noqa: E501
"""closeup.py OUT.png DIR:KEY[,KEY...] [DIR2 ...]: per pair a row cropped to the car (target mask and the input's car,
enlarged): input, exact target, each DIR's drawing (probe.py's npz) with its |error| x3, and the first DIR's part
map and source-code map. Each panel titled."""

from __future__ import annotations

import sys

import numpy as np
from PIL import Image, ImageDraw

from sdn3d.editing.photo.settings import SOURCE_COLORS, SOURCE_NAMES

PART_COLORS = {-1: (0, 0, 0), 0: (150, 150, 150), 1: (60, 120, 255), 2: (40, 40, 40), 3: (255, 255, 120), 4: (255, 40, 40), 5: (80, 220, 80)}
PART_NAMES = {0: "body", 1: "glass", 2: "tyre", 3: "front", 4: "tail", 5: "plate"}


def crop_box(car: np.ndarray, pad: int = 6) -> tuple[int, int, int, int]:
    ys, xs = np.nonzero(car)
    return max(0, ys.min() - pad), ys.max() + pad + 1, max(0, xs.min() - pad), xs.max() + pad + 1


def to_img(a: np.ndarray) -> np.ndarray:
    return (np.clip(a.transpose(1, 2, 0), 0, 1) * 255).astype(np.uint8)


def main() -> None:
    out, dirs, keys = sys.argv[1], sys.argv[3:], sys.argv[2].split(",")
    rows = []
    for key in keys:
        data = [np.load(f"{d.split('=')[-1]}/{key}.npz") for d in dirs]
        names = [d.split("=")[0] if "=" in d else d for d in dirs]
        d0 = data[0]
        y0, y1, x0, x1 = crop_box(d0["car"] | (np.abs(d0["input"] - d0["target"]).sum(0) > 0.05) & d0["car"])
        scale = max(2, min(8, 160 // max(1, y1 - y0)))
        panels = [("input", to_img(d0["input"])), ("target", to_img(d0["target"]))]
        for n, d in zip(names, data, strict=True):
            panels.append((n, to_img(d["drawn"])))
            err = np.abs(d["drawn"] - d["target"]).mean(0) * 3 * d["car"]
            panels.append((f"|{n}-target|x3", (np.clip(err, 0, 1)[..., None].repeat(3, -1) * 255).astype(np.uint8)))
        parts = d0["parts"].astype(int)
        pm = np.zeros(parts.shape + (3,), np.uint8)
        for k, c in PART_COLORS.items():
            pm[parts == k] = c
        panels.append((f"{names[0]} parts: grey body, blue glass, yellow front, red tail, green plate", pm))
        cm = np.array(SOURCE_COLORS, np.uint8)[d0["codes"].astype(int)]
        panels.append((f"{names[0]} source codes", cm))
        tiles = []
        for title, img in panels:
            c = Image.fromarray(np.ascontiguousarray(img[y0:y1, x0:x1])).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST)
            t = Image.new("RGB", (max(c.width, 120), c.height + 14), "white")
            t.paste(c, (0, 14))
            ImageDraw.Draw(t).text((2, 1), title[:40], fill=(0, 0, 160))
            tiles.append(t)
        w = sum(t.width + 4 for t in tiles)
        h = max(t.height for t in tiles) + 14
        row = Image.new("RGB", (w, h), "white")
        ImageDraw.Draw(row).text((2, 1), key, fill=(0, 0, 0))
        x = 0
        for t in tiles:
            row.paste(t, (x, 14))
            x += t.width + 4
        rows.append(row)
    legend = ", ".join(f"{n}" for n in SOURCE_NAMES)
    W = max(r.width for r in rows)
    canvas = Image.new("RGB", (W, sum(r.height for r in rows) + 16), "white")
    ImageDraw.Draw(canvas).text((2, 2), f"source codes: {legend}", fill=(0, 0, 0))
    y = 16
    for r in rows:
        canvas.paste(r, (0, y))
        y += r.height
    canvas.save(out)


if __name__ == "__main__":
    main()
