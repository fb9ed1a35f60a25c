"""bias.py BIN CODE PART REC.pt [REC.pt ...]: how much of one (source code, part) cell's error is a per-pair colour
offset (probe.py's records, session 24 turn41's): per pair, the cell's pixels on the car's target pixels, their MSE
(mean over RGB) and mean signed offset drawn - target; pooled: the cell's PSNR, MSE, and MSE with each pair's mean
RGB offset removed (what is left is where the colours lie, not their level); then the 20 pairs with most error.

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session25/back41/bias.py "turn 180" part \\
        GLASS /tmp/s25data/back41/bench/main_cf3{1,3,9}_oracle.pt
"""

from __future__ import annotations

import math
import sys

import torch

from sdn3d.editing.photo.light import luminance
from sdn3d.editing.photo.settings import SOURCE_NAMES
from sdn3d.meshes.parts import Part


def main() -> int:
    bin_, code, part = sys.argv[1], SOURCE_NAMES.index(sys.argv[2]), int(getattr(Part, sys.argv[3]))
    rows = []
    for path in sys.argv[4:]:
        for key, rec in torch.load(path, weights_only=False).items():
            crops = rec["crops"]
            if rec["bin"] != bin_ or crops["parts"] is None:
                continue
            cell = crops["car"] & (crops["source"] == code) & (crops["parts"] == part)
            if int(cell.sum()) < 20:
                continue
            drawn, target = crops["picture"].float() / 255, crops["target"].float() / 255
            err = (drawn - target)[:, cell]
            rows.append((key, int(cell.sum()), float(err.pow(2).mean()), float(err.mean()),
                         float(luminance(drawn[:, cell].T).mean()), float(luminance(target[:, cell].T).mean()),
                         float((err - err.mean(1, keepdim=True)).pow(2).mean())))
    pixels = sum(r[1] for r in rows)
    total = sum(r[1] * r[2] for r in rows)
    unbiased = sum(r[1] * r[6] for r in rows) / pixels
    psnr, offset = 10 * math.log10(pixels / total), sum(r[1] * r[3] for r in rows) / pixels
    print(f"{bin_} {sys.argv[2]} {sys.argv[3]}: {len(rows)} pairs, {pixels} pixels, PSNR {psnr:.2f}, MSE"
          f" {total / pixels:.5f}, less each pair's mean offset {unbiased:.5f} ({1 - unbiased * pixels / total:.0%}"
          f" of the MSE is offset), pooled signed offset {offset:+.4f}")
    for r in sorted(rows, key=lambda r: -r[1] * r[2])[:20]:
        print(f"{r[0]:52s} px {r[1]:5d} error share {r[1] * r[2] / total:.3f} MSE {r[2]:.4f} offset {r[3]:+.3f}"
              f" drawn luma {r[4]:.3f} target luma {r[5]:.3f} MSE less offset {r[6]:.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
