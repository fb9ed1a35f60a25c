"""panels.py OUT.png TITLE DUMP:ENTRY[:LABEL] ...: labelled strips of Table 1 dump entries (session 11 semrain's
dbench.py): per entry the input, the target, 3D-SDN, the 2D paste, 3D-SDN's source codes (fill yellow, completion
green/blue/orange, in front white) with the removed proposal outlined in red and the 'all' region in cyan,
cropped to the region and the proposal (24 px around), 4x enlarged. A DUMP given as A|B (two runs of the same
entry, e.g. main|branch) adds B's 3D-SDN picture after A's.
Run with /work/main/.venv/bin/python (numpy, Pillow)."""
import sys

import numpy as np
from PIL import Image, ImageDraw

COLORS = np.array([(40, 40, 40), (60, 170, 75), (70, 120, 230), (230, 80, 60), (240, 200, 60), (200, 90, 220),
                   (120, 120, 120), (150, 220, 230), (250, 140, 20), (170, 150, 110), (255, 255, 255),
                   (40, 140, 130)], np.uint8)
SCALE = 4
MARGIN = 24  # working pixels around the region in the crop


def psnr(a: np.ndarray, t: np.ndarray, reg: np.ndarray) -> float:
    e = ((a.astype(np.float64) - t) / 255) ** 2
    return 10 * np.log10(1 / max(e[reg].mean(), 1e-12))


def edge(m: np.ndarray) -> np.ndarray:
    p = np.pad(m, 1)
    inner = p[:-2, 1:-1] & p[2:, 1:-1] & p[1:-1, :-2] & p[1:-1, 2:]
    return m & ~inner


def tile(img: np.ndarray, title: str, box: tuple[int, int, int, int] | None = None) -> Image.Image:
    if box is not None:
        img = img[box[1]:box[3], box[0]:box[2]]
    im = Image.fromarray(np.ascontiguousarray(img)).resize((img.shape[1] * SCALE, img.shape[0] * SCALE), Image.NEAREST)
    canvas = Image.new("RGB", (im.width, im.height + 16), (255, 255, 255))
    canvas.paste(im, (0, 16))
    ImageDraw.Draw(canvas).text((2, 2), title, fill=(0, 0, 0))
    return canvas


def row(spec: str) -> list[Image.Image]:
    parts = spec.split(":")
    runs, entry = parts[0].split("|"), parts[1]
    label = parts[2] if len(parts) > 2 else ""
    names = [r.rstrip("/").split("/")[-1].replace(".dump", "") for r in runs]
    ds = [np.load(f"{r}/{int(entry):04d}.npz") for r in runs]
    d = ds[0]
    reg = d["region"]
    t = d["target"].astype(np.float64)
    code = COLORS[d["code"]] if d["code"].shape == reg.shape else np.zeros_like(d["source"])
    pick = np.isin(d["proposals"], d["picks"])
    code = code.copy()
    code[edge(pick)] = (255, 0, 0)
    code[edge(reg)] = (0, 255, 255)
    ys, xs = np.nonzero(reg | pick)
    h, w = reg.shape
    box = (max(int(xs.min()) - MARGIN, 0), max(int(ys.min()) - MARGIN, 0), min(int(xs.max()) + MARGIN + 1, w),
           min(int(ys.max()) + MARGIN + 1, h))
    tiles = [tile(d["source"], f"{names[0]} e{entry} {str(d['kind'])} {label}: input", box),
             tile(d["target"], "target (ground truth)", box)]
    for n, x in zip(names, ds, strict=True):
        tiles.append(tile(x["sdn"], f"3D-SDN ({n}) {psnr(x['sdn'], t, reg):.2f} dB", box))
    tiles.append(tile(d["d2"], f"2D paste {psnr(d['d2'], t, reg):.2f} dB", box))
    tiles.append(tile(code, f"3D-SDN codes ({names[0]}); red: proposal", box))
    return tiles


def main(out: str, title: str, specs: list[str]) -> None:
    rows = [row(s) for s in specs]
    w = max(sum(t.width for t in r) for r in rows)
    h = sum(max(t.height for t in r) for r in rows) + 20
    sheet = Image.new("RGB", (w, h), (255, 255, 255))
    ImageDraw.Draw(sheet).text((4, 4), title, fill=(0, 0, 0))
    y = 20
    for r in rows:
        x = 0
        for t in r:
            sheet.paste(t, (x, y))
            x += t.width
        y += max(t.height for t in r)
    sheet.save(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
