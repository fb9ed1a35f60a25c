"""Labelled panels of the spec31 edit by both codes: ``picture.py IDENTITY_DIR INPUT_PNG OUT_PNG``.

IDENTITY_DIR is identity.sh's folder (``main/`` and ``cost40/`` outputs). Panels, each titled: the input, main's
edited.png, this branch's edited.png, and |branch - main| amplified x50 (black where equal).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw


def _titled(image: np.ndarray, title: str) -> np.ndarray:
    bar = Image.new("RGB", (image.shape[1], 18), (255, 255, 255))
    ImageDraw.Draw(bar).text((4, 3), title, fill=(0, 0, 0))
    return np.concatenate([np.asarray(bar), image], 0)


def main() -> None:
    folder, source, out = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
    src = np.asarray(Image.open(source).convert("RGB"))
    main_, branch = (np.asarray(Image.open(folder / n / "edited.png").convert("RGB")) for n in ("main", "cost40"))
    diff = np.abs(branch.astype(np.int16) - main_.astype(np.int16))
    amplified = np.clip(diff * 50, 0, 255).astype(np.uint8)
    panels = [_titled(src, "input (seed-31 frame, 624x192, 10 boxes)"),
              _titled(main_, "sdn3d-edit, main 9fa5234: car 12005 turned 30 deg"),
              _titled(branch, "sdn3d-edit, branch s26-cost40: the same edit"),
              _titled(amplified, f"|branch - main| x50: max {int(diff.max())}, "
                                 f"{int((diff > 0).any(2).sum())} px differ")]
    Image.fromarray(np.concatenate(panels, 0)).save(out, optimize=True)


if __name__ == "__main__":
    main()
