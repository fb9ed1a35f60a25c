# ruff: noqa: E501
"""latency.py WEIGHTS: CPU time (1 thread) of the learnt correction alone on the real frame of tests/data (1242x375)
with the hole of a car-sized box (the red car's, 200x130 px, plus the black car's, 213x111), median of 20 runs; and
of fill_hole with fill=rays and fill=learnt on the same hole (level-camera vanishing point)."""
import sys
import time
from pathlib import Path

import numpy as np
import torch
from PIL import Image

from sdn3d.editing.photo.fill import fill_hole
from sdn3d.editing.photo.learnt import learnt_fill, load_fill_net
from sdn3d.editing.photo.settings import PhotoSettings

torch.set_num_threads(1)
root = Path(__file__).resolve().parents[5]
image = torch.from_numpy(np.array(Image.open(root / "tests/data/0006_30-deg-right_00043.png").convert("RGB"))).permute(2, 0, 1).float() / 255
hole = torch.zeros(image.shape[1:], dtype=torch.bool)
hole[203:333, 466:666] = True
hole[194:305, 704:917] = True
net = load_fill_net(sys.argv[1])


def cpu_ms(fn, n):
    out = []
    for _ in range(n):
        t = time.process_time()
        fn()
        out.append(1000 * (time.process_time() - t))
    return float(np.median(out))


print(f"picture {tuple(image.shape)}, hole {int(hole.sum())} px in 2 parts")
print(f"learnt correction alone: {cpu_ms(lambda: learnt_fill(image, hole, net), 20):.1f} ms CPU (median of 20)")
for fill in ("rays", "learnt"):
    s = PhotoSettings(fill=fill, learnt_weights=sys.argv[1])
    print(f"fill_hole fill={fill}: {cpu_ms(lambda s=s: fill_hole(image, hole, s), 5):.1f} ms CPU (median of 5)")
