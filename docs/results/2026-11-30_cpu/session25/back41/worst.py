"""worst.py OUT_PNG: the cells with most of a turn's error on main (probe.py's records of main 9a61b5b on the tuning
trees, /tmp/s25data/back41/bench), one row per case, every panel titled: the input, the target (the car really
turned), main's picture with its car PSNR, main's source map (``source_picture``'s colours: photo green, mirror blue,
part light cyan, default orange, fill yellow) and the part map main drew by (glass blue, body light grey, other
parts black) with the pixels it calls glass where the target is light (luma > 0.4) in red: the template's greenhouse
where the generator's vehicle shape has paint. Ground-truth geometry (oracle); crops scaled 2x.

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session25/back41/worst.py OUT_PNG
"""

from __future__ import annotations

import math
import sys

import numpy as np
import torch
from PIL import Image

from sdn3d.editing.photo.settings import source_picture
from sdn3d.meshes.parts import Part
from sdn3d.visualize import titled_row

B = "/tmp/s25data/back41/bench"
CASES = (("main_cf33_oracle.pt", "oracle|0006/clone/00029_13005 turn_180"),
         ("main_cf31_oracle.pt", "oracle|0018/clone/00026_13008 turn_90"),
         ("main_cf31_oracle.pt", "oracle|0018/clone/00028_13008 turn_180"))


def big(a: np.ndarray) -> np.ndarray:
    return np.asarray(Image.fromarray(a).resize((2 * a.shape[1], 2 * a.shape[0]), Image.NEAREST))


def main() -> int:
    rows = []
    for rec, key in CASES:
        c = torch.load(f"{B}/{rec}", weights_only=False)[key]["crops"]
        car = c["car"]
        err = ((c["picture"].float() - c["target"].float()) / 255)[:, car].pow(2).mean()
        parts = c["parts"].long()
        light = (c["target"].float() / 255).mean(0) > 0.4
        pm = np.zeros((*parts.shape, 3), np.uint8)
        pm[(parts == int(Part.GLASS)).numpy()] = (60, 60, 200)
        pm[(parts == int(Part.BODY)).numpy()] = (200, 200, 200)
        pm[((parts == int(Part.GLASS)) & light & car).numpy()] = (230, 30, 30)
        name = key.split("|")[1]
        rows.append(titled_row([
            (f"{name} (oracle): input", big(c["input"].permute(1, 2, 0).numpy())),
            ("target (the car turned)", big(c["target"].permute(1, 2, 0).numpy())),
            (f"main 9a61b5b: {10 * math.log10(1 / float(err)):.2f} dB", big(c["picture"].permute(1, 2, 0).numpy())),
            ("main: source map", big(source_picture(c["source"]).permute(1, 2, 0).numpy()
                                     if torch.is_tensor(source_picture(c["source"])) else source_picture(c["source"]))),
            ("main: parts (red: glass, target light)", big(pm))]))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).save(sys.argv[1])
    return 0


if __name__ == "__main__":
    sys.exit(main())
