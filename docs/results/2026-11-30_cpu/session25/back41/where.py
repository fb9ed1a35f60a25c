"""Session 23 front: where a turned car's target-pixel error lies (probe.py's records): per source scene and turn bin,
each (source code, part) cell's share of the car pixels, its share of the summed squared error and its own PSNR,
pooled over the records given (largest error share first; cells under 1 % of the error left out).

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session23/front/where.py REC.pt [REC.pt ...]
"""

from __future__ import annotations

import math
import sys
from collections import defaultdict

import torch

from sdn3d.editing.photo.settings import SOURCE_NAMES
from sdn3d.meshes.parts import PART_NAMES

LABELS = {"oracle": "ground-truth geometry (oracle)", "semantic": "predicted"}


def main() -> int:
    pooled: dict[tuple[str, str], dict] = defaultdict(lambda: defaultdict(lambda: [0, 0.0]))
    pairs: dict[tuple[str, str], int] = defaultdict(int)
    for path in sys.argv[1:]:
        for rec in torch.load(path, weights_only=False).values():
            group = (rec["source"], rec["bin"])
            pairs[group] += 1
            for cell, (n, sse) in rec["cells"].items():
                pooled[group][cell][0] += n
                pooled[group][cell][1] += sse
    print("| source scene | bin | pairs | source code | part | pixel share | error share | PSNR of the cell |")
    print("|---|---|---|---|---|---|---|---|")
    for group in sorted(pooled, key=lambda g: (g[0], int(g[1].split()[-1]))):
        cells = pooled[group]
        n_all = sum(v[0] for v in cells.values())
        e_all = sum(v[1] for v in cells.values())
        for (code, part), (n, sse) in sorted(cells.items(), key=lambda c: -c[1][1]):
            if sse < 0.01 * e_all:
                continue
            psnr = 10 * math.log10(1 / max(sse / n, 1e-10))
            name = PART_NAMES[part] if part >= 0 else "none"
            print(f"| {LABELS[group[0]]} | {group[1]} | {pairs[group]} | {SOURCE_NAMES[code]} | {name} | "
                  f"{n / n_all:.3f} | {sse / e_all:.3f} | {psnr:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
