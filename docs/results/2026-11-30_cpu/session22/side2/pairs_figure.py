"""Session 22 side2: counterfactual turn pairs drawn by two codes (probe.py's $CAPTURE files), one row per pair:
the input, the target (the car really turned), code A's picture and code B's, each cropped around the car and
titled (what, which code, the car pixels' PSNR), scaled up 2x; written to OUT_PNG.

    PYTHONPATH=src /work/main/.venv/bin/python pairs_figure.py OUT_PNG LABEL_A A.pt LABEL_B B.pt
"""

from __future__ import annotations

import math
import sys

import numpy as np
import torch
from PIL import Image

from sdn3d.visualize import titled_row


def crop_box(car: torch.Tensor, height: int, width: int) -> tuple[int, int, int, int]:
    ys, xs = car.nonzero(as_tuple=True)
    y0, y1, x0, x1 = int(ys.min()), int(ys.max()), int(xs.min()), int(xs.max())
    pad = 12
    return max(0, y0 - pad), min(height, y1 + pad), max(0, x0 - pad), min(width, x1 + pad)


def psnr(picture: torch.Tensor, target: torch.Tensor, car: torch.Tensor) -> float:
    err = ((picture.float() - target.float()) / 255)[:, car].pow(2).mean()
    return float(10 * math.log10(1 / max(float(err), 1e-10)))


def main() -> int:
    out, label_a, path_a, label_b, path_b = sys.argv[1:6]
    a, b = torch.load(path_a, weights_only=False), torch.load(path_b, weights_only=False)
    rows = []
    for key in sorted(set(a) & set(b), key=lambda k: (k.split()[0], int(k.rsplit("_", 1)[-1]))):
        pa, pb = a[key], b[key]
        car = pa["car"] | pa["picture"].ne(pb["picture"]).any(0)
        height, width = car.shape
        y0, y1, x0, x1 = crop_box(pa["car"], height, width)

        def show(image: torch.Tensor, y0=y0, y1=y1, x0=x0, x1=x1) -> np.ndarray:
            crop = image[:, y0:y1, x0:x1].permute(1, 2, 0).numpy()
            return np.asarray(Image.fromarray(crop).resize((2 * crop.shape[1], 2 * crop.shape[0]), Image.NEAREST))

        name = key.replace("turn_", "turn ")
        rows.append(titled_row([(f"{name}: input", show(pa["input"])), ("target (the car turned)", show(pa["target"])),
                                (f"{label_a}: {psnr(pa['picture'], pa['target'], pa['car']):.2f} dB",
                                 show(pa["picture"])),
                                (f"{label_b}: {psnr(pb['picture'], pb['target'], pb['car']):.2f} dB",
                                 show(pb["picture"]))], font_size=14))
    width = max(r.shape[1] for r in rows)
    rows = [np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows]
    Image.fromarray(np.concatenate(rows, 0)).save(out)
    print(out, len(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
