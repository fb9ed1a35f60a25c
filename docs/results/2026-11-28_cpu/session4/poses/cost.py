import time

import torch

from sdn3d.geometric.fit import FitSettings, fit_to_masks
from sdn3d.math3d.camera import Intrinsics

torch.set_num_threads(1)
intr = Intrinsics(362.5, 362.5, 310.25, 93.5, 624, 192)
masks = torch.zeros(6, 192, 624, dtype=torch.bool)
boxes = []
for i in range(6):
    x0 = 20 + i * 100
    masks[i, 90:140, x0:x0 + 80] = True
    boxes.append([x0, 90, x0 + 80, 140])
boxes = torch.tensor(boxes, dtype=torch.float32)
kw = dict(start_ry=torch.full((6,), -1.2), start_dims=torch.tensor([[4.0, 1.5, 1.7]]).expand(6, 3),
          start_template=torch.full((6,), 2), start_location=torch.tensor([[0.0, 1.65, 10.0]]).expand(6, 3))
times = {True: [], False: []}
for _rep in range(3):
    for mirror in (False, True):
        t = time.perf_counter()
        fit_to_masks(masks, boxes, intr, settings=FitSettings(mirror=mirror), **kw)
        times[mirror].append(time.perf_counter() - t)
print({k: [round(x, 2) for x in v] for k, v in times.items()})
print("ratio of medians", sorted(times[True])[1] / sorted(times[False])[1])
