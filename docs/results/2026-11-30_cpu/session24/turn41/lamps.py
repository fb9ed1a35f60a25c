"""Session 23 front: the never-seen end's default lamps (probe.py's records): per 180-degree pair with at least 5
car pixels drawn in a default colour on the body (the lamp band, ``LAMP_DEFAULTS``), their count, mean drawn and
target RGB, the target's spread, their MSE and the pair's car PSNR.

    PYTHONPATH=src /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session23/front/lamps.py REC.pt ...
"""

from __future__ import annotations

import sys

import torch

from sdn3d.editing.photo.settings import DEFAULT
from sdn3d.meshes.parts import Part


def main() -> int:
    for path in sys.argv[1:]:
        for key, rec in torch.load(path, weights_only=False).items():
            c = rec["crops"]
            m = (c["source"] == DEFAULT) & c["car"] & (c["parts"] == int(Part.BODY))
            if rec["bin"] != "turn 180" or int(m.sum()) < 5:
                continue
            p, t = c["picture"].float()[:, m] / 255, c["target"].float()[:, m] / 255
            print(f"{key}: {int(m.sum())} px, drawn {[round(v, 2) for v in p.mean(1).tolist()]}, target "
                  f"{[round(v, 2) for v in t.mean(1).tolist()]} (spread {float(t.std(1).mean()):.2f}), "
                  f"MSE {float(((p - t) ** 2).mean()):.3f}, car PSNR {rec['psnr']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
