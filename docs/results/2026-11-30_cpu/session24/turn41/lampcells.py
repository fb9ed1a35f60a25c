"""Session 24 turn41: the never-seen end's lamp band (probe.py's records): per source scene and turn bin, the car
pixels drawn on the body in a default colour (``LAMP_DEFAULTS``, code ``default``) or from another car (code
``another car``), split by the lamp they draw (drawn red, R - G over 0.1: tail lamps; else head lamps): share of
the bin's car pixels, share of its summed squared error, the cell's own PSNR, its mean drawn and target sRGB.

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session24/turn41/lampcells.py REC.pt ...
"""

from __future__ import annotations

import math
import sys
from collections import defaultdict

import torch

from sdn3d.editing.photo.settings import ANOTHER_CAR, DEFAULT, SOURCE_NAMES
from sdn3d.meshes.parts import Part

LABELS = {"oracle": "ground-truth geometry (oracle)", "semantic": "predicted"}


def main() -> int:
    cells: dict[tuple, list] = defaultdict(lambda: [0, 0.0, torch.zeros(3), torch.zeros(3)])
    totals: dict[tuple, list] = defaultdict(lambda: [0, 0.0])
    for path in sys.argv[1:]:
        for rec in torch.load(path, weights_only=False).values():
            c, group = rec["crops"], (rec["source"], rec["bin"])
            for n, sse in rec["cells"].values():
                totals[group][0] += n
                totals[group][1] += sse
            p, t = c["picture"].float() / 255, c["target"].float() / 255
            err = ((p - t) ** 2).mean(0)
            for code in (DEFAULT, ANOTHER_CAR):
                m = (c["source"] == code) & c["car"] & (c["parts"] == int(Part.BODY))
                red = (p[0] - p[1] > 0.1) & m  # red drawn (in fog too: hazed, pink)
                for lamp, here in (("tail lamps (red)", red), ("head lamps", m & ~red)):
                    if not bool(here.any()):
                        continue
                    cell = cells[(*group, SOURCE_NAMES[code], lamp)]
                    cell[0] += int(here.sum())
                    cell[1] += float(err[here].sum())
                    cell[2] += p[:, here].sum(1)
                    cell[3] += t[:, here].sum(1)
    print("| source scene | bin | code | lamp | pixel share | error share | PSNR of the cell | drawn sRGB "
          "| target sRGB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for key in sorted(cells, key=lambda g: (g[0], int(g[1].split()[-1]), g[2], g[3])):
        n, sse, drawn, target = cells[key]
        total = totals[key[:2]]
        psnr = 10 * math.log10(n / max(sse, 1e-12))
        print(f"| {LABELS.get(key[0], key[0])} | {key[1]} | {key[2]} | {key[3]} | {n / total[0]:.4f} | "
              f"{sse / total[1]:.4f} | {psnr:.2f} | {[round(v, 2) for v in (drawn / n).tolist()]} | "
              f"{[round(v, 2) for v in (target / n).tolist()]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
