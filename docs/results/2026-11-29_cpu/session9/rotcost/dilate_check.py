# ruff: noqa: E402, E501, E701, E702
"""dilate_check.py: image_ops.dilate_square (running counts above a radius of 48) against OpenCV's dilation as it was,
on the dilate_square calls of lat3's rotate edits (capture_calls.py; CPU ms per edit, old then new) and on 300 random
masks of small pictures at radii 49 to 120; asserts equality."""
import pickle
import time

import cv2
import numpy as np
import torch

torch.set_num_threads(1)
from sdn3d.image_ops import dilate_square


def old(mask, radius):
    if radius <= 0 or not bool(mask.any()): return mask
    kernel = np.ones((2 * radius + 1, 2 * radius + 1), np.uint8)
    return torch.from_numpy(cv2.dilate(mask.numpy().astype(np.uint8), kernel) > 0)
rec = pickle.load(open("/tmp/s9data/rotcost/cap/rotate_calls.pkl", "rb"))
t_old = t_new = 0
for m, r in rec["dilate"]:
    t = time.process_time(); a = old(m, r); t1 = time.process_time(); b = dilate_square(m, r); t2 = time.process_time()
    assert torch.equal(a, b), r
    t_old += t1 - t; t_new += t2 - t1
print(f"captured: old {1000*t_old/6:.1f} new {1000*t_new/6:.1f} ms/edit")
g = torch.Generator().manual_seed(0)
for _trial in range(300):
    h, w = int(torch.randint(1, 60, (1,), generator=g)), int(torch.randint(1, 90, (1,), generator=g))
    m = torch.rand(h, w, generator=g) < float(torch.rand(1, generator=g)) ** 3
    for r in (49, 50, 63, 100):
        # small pictures: scale the radius down to exercise the windows
        rr = int(torch.randint(1, 120, (1,), generator=g))
        for radius in (r, rr):
            assert torch.equal(old(m, radius), dilate_square(m, radius)), (h, w, radius)
print("random ok")
