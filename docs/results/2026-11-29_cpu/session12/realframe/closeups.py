"""closeups.py BEFORE_DIR AFTER_DIR OUT.png: close-ups at twice the input's size from two probe.py outputs (main's
code, this branch's): the black car (12002) as input, recoloured blue by main and by this branch; the red car
(12001) turned 90 degrees by main and by this branch, and the source map of this branch's turn (light cyan: the car's
parts seen elsewhere, blue: mirror, green: photo, yellow: fill, grey: shadow; settings.SOURCE_COLORS)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"


def main() -> int:
    import torch

    from sdn3d.editing.photo.settings import source_picture
    from sdn3d.visualize import titled_row

    before, after, out = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
    frame = np.asarray(Image.open(FRAME).convert("RGB"))

    def crop(image: np.ndarray, box: tuple[int, int, int, int]) -> np.ndarray:
        x0, y0, x1, y1 = box
        return np.asarray(Image.fromarray(np.ascontiguousarray(image[y0:y1, x0:x1])).resize(
            ((x1 - x0) * 2, (y1 - y0) * 2), Image.NEAREST))

    def edited(folder: Path, name: str) -> np.ndarray:
        return np.load(folder / f"{name}.npz")["edited"]

    black, red = (690, 180, 930, 320), (420, 170, 740, 350)
    source = source_picture(torch.from_numpy(np.load(after / "12001_turned_90.npz")["source"]))
    rows = [titled_row([("12002 input", crop(frame, black)),
                        ("12002 recoloured blue, main", crop(edited(before, "12002_recoloured_blue"), black)),
                        ("12002 recoloured blue, this branch", crop(edited(after, "12002_recoloured_blue"), black))]),
            titled_row([("12001 turned 90, main", crop(edited(before, "12001_turned_90"), red)),
                        ("12001 turned 90, this branch", crop(edited(after, "12001_turned_90"), red)),
                        ("12001 turned 90, this branch: source map", crop(source, red))])]
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    picture = Image.fromarray(grid)
    picture = picture.resize((picture.width * 2 // 3, picture.height * 2 // 3), Image.LANCZOS)
    picture.quantize(256).save(out, optimize=True)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
