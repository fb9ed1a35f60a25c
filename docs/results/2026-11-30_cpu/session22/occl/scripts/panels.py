"""panels.py OUT.png TITLE DUMP:ENTRY[:LABEL] [...]: labelled panels of Table 1 dbench.py dump entries, one row per
entry: source, target, 3D-SDN and the 2D paste (each with the 'all' region's outline in yellow), and the absolute
error of each against the target (x3), each panel titled with what it is and which run (LABEL, else the dump's name)
drew it. Run with /work/main/.venv/bin/python (numpy, Pillow)."""
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

SCALE = 4
#: The panels show a window of this many rows and columns about the 'all' region's centre (inside the picture).
WINDOW = (48, 120)


def outline(img: np.ndarray, region: np.ndarray) -> np.ndarray:
    r = region.astype(bool)
    edge = r & ~(np.roll(r, 1, 0) & np.roll(r, -1, 0) & np.roll(r, 1, 1) & np.roll(r, -1, 1))
    out = img.copy()
    out[edge] = (255, 230, 0)
    return out


def tile(img: np.ndarray, title: str) -> Image.Image:
    h, w = img.shape[:2]
    im = Image.fromarray(img.astype(np.uint8)).resize((w * SCALE, h * SCALE), Image.NEAREST)
    canvas = Image.new("RGB", (w * SCALE, h * SCALE + 14), (255, 255, 255))
    canvas.paste(im, (0, 14))
    ImageDraw.Draw(canvas).text((2, 1), title, fill=(0, 0, 0))
    return canvas


def row(spec: str) -> list[Image.Image]:
    parts = spec.split(":")
    dump, index = parts[0], parts[1]
    label = parts[2] if len(parts) > 2 else Path(dump).name
    d = np.load(Path(dump) / f"{int(index):04d}.npz")
    t = d["target"].astype(np.float64)
    reg = d["region"]
    ys, xs = np.nonzero(reg)
    cy, cx = (int(ys.mean()), int(xs.mean())) if len(ys) else (reg.shape[0] // 2, reg.shape[1] // 2)
    y0 = min(max(cy - WINDOW[0] // 2, 0), reg.shape[0] - WINDOW[0])
    x0 = min(max(cx - WINDOW[1] // 2, 0), reg.shape[1] - WINDOW[1])
    win = (slice(y0, y0 + WINDOW[0]), slice(x0, x0 + WINDOW[1]))

    def err(x: np.ndarray) -> np.ndarray:
        return np.clip(np.abs(x.astype(np.float64) - t) * 3, 0, 255)

    def psnr(x: np.ndarray) -> float:
        mse = (((x.astype(np.float64) - t) / 255) ** 2)[reg].mean()
        return 10 * np.log10(1 / max(mse, 1e-12))

    def crop(img: np.ndarray) -> np.ndarray:
        return img[win]

    return [tile(crop(outline(d["source"], reg)), f"{label} e{index} source ({d['kind']})"),
            tile(crop(outline(d["target"], reg)), "target (ground truth)"),
            tile(crop(outline(d["sdn"], reg)), f"3D-SDN, {label}: {psnr(d['sdn']):.2f} dB"),
            tile(crop(outline(d["d2"], reg)), f"2D paste, {label}: {psnr(d['d2']):.2f} dB"),
            tile(crop(err(d["sdn"])), f"|3D-SDN - target| x3, {label}"),
            tile(crop(err(d["d2"])), f"|2D - target| x3, {label}")]


def main(out: str, title: str, specs: list[str]) -> None:
    rows = [row(s) for s in specs]
    w, h = rows[0][0].size
    sheet = Image.new("RGB", (w * 6, h * len(rows) + 18), (255, 255, 255))
    ImageDraw.Draw(sheet).text((4, 3), title, fill=(0, 0, 0))
    for i, r in enumerate(rows):
        for j, t in enumerate(r):
            sheet.paste(t, (j * w, 18 + i * h))
    tmp = Path(out).with_suffix(".tmp.png")
    sheet.save(tmp)
    tmp.replace(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
