"""island_figure.py MAIN_DIR BRANCH_DIR OUT.png MAIN_LABEL BRANCH_LABEL: the real frame's deletes (redraw.py
outputs, NAME.npz) drawn by main and the branch: per car a row of input, main, branch over the car's surroundings
(twice the size), and for the black car a close-up (four times) on the traffic island right of it; every panel
titled. Prints the pixels the two codes draw differently per edit.

    PYTHONPATH=src python island_figure.py /tmp/s21data/island/real_main /tmp/s21data/island/real_br OUT.png \\
        "main (debaff5)" "branch (s21-island)"
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
#: (x0, y0, x1, y1) shown per delete, and the black car's island close-up.
VIEWS = {"12001_deleted": ("red car", (430, 190, 690, 360)), "12002_deleted": ("black car", (640, 185, 960, 330))}
ISLAND = (760, 215, 940, 285)


def panel(picture: np.ndarray, box: tuple[int, int, int, int], scale: int, title: str) -> Image.Image:
    x0, y0, x1, y1 = box
    crop = Image.fromarray(picture[y0:y1, x0:x1]).resize(((x1 - x0) * scale, (y1 - y0) * scale), Image.NEAREST)
    out = Image.new("RGB", (crop.width, crop.height + 14), "white")
    out.paste(crop, (0, 14))
    ImageDraw.Draw(out).text((2, 1), title, fill="black")
    return out


def row(panels: list[Image.Image]) -> Image.Image:
    out = Image.new("RGB", (sum(p.width for p in panels) + 4 * len(panels), max(p.height for p in panels)), "white")
    x = 0
    for p in panels:
        out.paste(p, (x, 0))
        x += p.width + 4
    return out


def main() -> int:
    main_dir, branch_dir, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    labels = sys.argv[4], sys.argv[5]
    frame = np.array(Image.open(FRAME).convert("RGB"))
    rows = []
    for name, (what, box) in VIEWS.items():
        a, b = (np.load(d / f"{name}.npz")["edited"] for d in (main_dir, branch_dir))
        print(name, "pixels drawn differently:", int(np.any(a != b, axis=2).sum()))
        rows.append(row([panel(frame, box, 2, f"input ({what})")]
                        + [panel(x, box, 2, f"{lab}: {what} deleted") for x, lab in zip((a, b), labels, strict=True)]))
        if name == "12002_deleted":
            rows.append(row([panel(frame, ISLAND, 4, "input, the island right of the black car")]
                            + [panel(x, ISLAND, 4, f"{lab}: black car deleted, island close-up")
                               for x, lab in zip((a, b), labels, strict=True)]))
    sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 6 for r in rows)), "white")
    y = 0
    for r in rows:
        sheet.paste(r, (0, y))
        y += r.height + 6
    sheet.save(out.with_suffix(".tmp.png"))
    out.with_suffix(".tmp.png").replace(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
