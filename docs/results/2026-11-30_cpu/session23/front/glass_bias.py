"""Session 23 front: the glass a turned car shows, drawn against the target (probe.py's records): per source scene,
turn bin and source code (photo, mirror, part), the mean drawn and target colour of the car's glass pixels, their
mean squared error, and that error were each pair's mean offset removed (how much of it a per-car brightness shift
of the glass could take away).

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session23/front/glass_bias.py REC.pt ...
"""

from __future__ import annotations

import sys
from collections import defaultdict

import torch

from sdn3d.editing.photo.settings import MIRROR, PART, PHOTO
from sdn3d.meshes.parts import Part


def main() -> int:
    acc: dict[tuple, list] = defaultdict(lambda: [0, torch.zeros(3), torch.zeros(3), 0.0, 0.0])
    for path in sys.argv[1:]:
        for rec in torch.load(path, weights_only=False).values():
            c = rec["crops"]
            for code, name in ((PART, "part"), (MIRROR, "mirror"), (PHOTO, "photo")):
                m = (c["source"] == code) & c["car"] & (c["parts"] == int(Part.GLASS))
                if not bool(m.any()):
                    continue
                p, t = c["picture"].float()[:, m] / 255, c["target"].float()[:, m] / 255
                a = acc[(rec["source"], rec["bin"], name)]
                a[0] += int(m.sum())
                a[1] += p.sum(1)
                a[2] += t.sum(1)
                a[3] += float(((p - t) ** 2).mean(0).sum())
                a[4] += float(((p + (t - p).mean(1, keepdim=True) - t) ** 2).mean(0).sum())
    print("| source scene | bin | code | pixels | drawn RGB | target RGB | MSE | MSE less each pair's offset |")
    print("|---|---|---|---|---|---|---|---|")
    for key in sorted(acc, key=lambda k: (k[0], int(k[1].split()[-1]), k[2])):
        n, p, t, e, e2 = acc[key]
        rgb = [", ".join(f"{v:.3f}" for v in (x / n).tolist()) for x in (p, t)]
        print(f"| {key[0]} | {key[1]} | {key[2]} | {n} | {rgb[0]} | {rgb[1]} | {e / n:.4f} | {e2 / n:.4f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
