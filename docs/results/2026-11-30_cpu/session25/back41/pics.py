"""Session 23 front: turn pairs drawn by one or two codes (probe.py's records), one row per pair: the input, the target
(the car really turned), each code's picture (titled with the code and the car pixels' PSNR) and its source map
(``source_picture``'s colours: photo green, mirror blue, part light cyan, default orange, fill yellow); crops around
the car, scaled 2x. KEYS: comma-separated substrings of the records' keys (``oracle|0006/clone/00027_12001
turn_180``); a pair is drawn when its key holds one of them.

    PYTHONPATH=src /work/main/.venv/bin/python pics.py OUT_PNG KEYS LABEL_A A.pt [LABEL_B B.pt]
"""

from __future__ import annotations

import math
import sys

import numpy as np
import torch
from PIL import Image

from sdn3d.editing.photo.settings import source_picture
from sdn3d.visualize import titled_row


def psnr(picture: torch.Tensor, target: torch.Tensor, car: torch.Tensor) -> float:
    err = ((picture.float() - target.float()) / 255)[:, car].pow(2).mean()
    return float(10 * math.log10(1 / max(float(err), 1e-10)))


def show(image: torch.Tensor) -> np.ndarray:
    crop = image.permute(1, 2, 0).numpy() if torch.is_tensor(image) else image
    return np.asarray(Image.fromarray(crop).resize((2 * crop.shape[1], 2 * crop.shape[0]), Image.NEAREST))


def main() -> int:
    out, keys = sys.argv[1], sys.argv[2].split(",")
    codes = [(sys.argv[i], torch.load(sys.argv[i + 1], weights_only=False)) for i in range(3, len(sys.argv), 2)]
    rows = []
    common = set.intersection(*(set(records) for _, records in codes))
    for key in sorted(k for k in common if any(s in k for s in keys)):
        first = codes[0][1][key]["crops"]
        panels = [(f"{key.split('|')[1].replace('turn_', 'turn ')} ({key.split('|')[0]}): input", show(first["input"])),
                  ("target (the car turned)", show(first["target"]))]
        for label, records in codes:
            c = records[key]["crops"]
            panels.append((f"{label}: {psnr(c['picture'], c['target'], c['car']):.2f} dB", show(c["picture"])))
            panels.append((f"{label}: source map", show(source_picture(c["source"]))))
        rows.append(titled_row(panels, font_size=13))
    width = max(r.shape[1] for r in rows)
    rows = [np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows]
    Image.fromarray(np.concatenate(rows, 0)).save(out)
    print(out, len(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
