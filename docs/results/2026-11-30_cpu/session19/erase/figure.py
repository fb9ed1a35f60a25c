# ruff: noqa: E501
"""figure.py OUT.png MAIN_CAPTURE[,MAIN_CAPTURE...] BRANCH_CAPTURE KEY[,KEY...]: per delete pair a row of titled
panels cropped around the hole (vacated region plus shadow band, outlined in the input panel): the input, the truth
(the exact render without the car), main's Telea, PatchMatch, rays and learnt, and the branch's rays and learnt, each
titled with its PSNR on the hole. Captures are capture.py's files; main's ran fills [telea,patchmatch,rays,learnt],
the branch's [rays,learnt] (the pictures are stored in that order)."""

from __future__ import annotations

import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

SCALE_ROWS = 150


def psnr(pred: torch.Tensor, target: torch.Tensor, mask: torch.Tensor) -> float:
    mse = float(((pred.clamp(0, 1) - target) ** 2)[:, mask].mean())
    return 10 * np.log10(1 / max(mse, 1e-10))


def tile(picture: torch.Tensor, box: tuple[int, int, int, int], scale: int, title: str, outline: torch.Tensor | None = None) -> Image.Image:
    y0, y1, x0, x1 = box
    a = (picture[:, y0:y1, x0:x1].clamp(0, 1).permute(1, 2, 0).numpy() * 255 + 0.5).astype(np.uint8)
    if outline is not None:  # the hole's edge in magenta
        m = outline[y0:y1, x0:x1].numpy()
        inner = m.copy()
        inner[1:-1, 1:-1] = m[1:-1, 1:-1] & m[:-2, 1:-1] & m[2:, 1:-1] & m[1:-1, :-2] & m[1:-1, 2:]
        a[m & ~inner] = (255, 0, 255)
    im = Image.fromarray(a).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST)
    out = Image.new("RGB", (max(im.width, 150), im.height + 16), "white")
    out.paste(im, (0, 16))
    ImageDraw.Draw(out).text((2, 2), title, fill="black")
    return out


def main() -> int:
    out, mains, branch, keys = sys.argv[1], sys.argv[2].split(","), sys.argv[3], sys.argv[4].split(",")
    base = {}
    for path in mains:
        base.update(torch.load(path, weights_only=False))
    ours = torch.load(branch, weights_only=False)
    rows = []
    for key in keys:
        k = next(x for x in base if key in x)
        e, b = base[k], ours[k]
        hole = e["masks"]["vacated"] | e["masks"]["shadow"]
        ys, xs = hole.nonzero(as_tuple=True)
        height, width = hole.shape
        m = 20
        box = (max(int(ys.min()) - m, 0), min(int(ys.max()) + m, height), max(int(xs.min()) - m, 0), min(int(xs.max()) + m, width))
        scale = max(1, SCALE_ROWS // (box[1] - box[0]))
        target = e["target"]
        panels = [("input", e["image"], hole), ("truth (render without the car)", target, None)]
        for name, pic in zip(("main Telea", "main PatchMatch", "main rays", "main learnt"), e["pics"][:4], strict=True):
            panels.append((name, pic, None))
        for name, pic in zip(("branch rays", "branch learnt"), b["pics"][:2], strict=True):
            panels.append((name, pic, None))
        tiles = [tile(p, box, scale, name if i < 2 else f"{name} {psnr(p, target, hole):.1f} dB", outline) for i, (name, p, outline) in enumerate(panels)]
        row = Image.new("RGB", (sum(t.width + 4 for t in tiles), max(t.height for t in tiles) + 16), "white")
        ImageDraw.Draw(row).text((2, 2), f"{k} (ground-truth geometry (oracle)); PSNR on the vacated region + shadow band", fill="black")
        x = 0
        for t in tiles:
            row.paste(t, (x, 16))
            x += t.width + 4
        rows.append(row)
    sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 6 for r in rows)), "white")
    y = 0
    for r in rows:
        sheet.paste(r, (0, y))
        y += r.height + 6
    sheet.save(out)
    print(out, sheet.size)
    return 0


if __name__ == "__main__":
    sys.exit(main())
