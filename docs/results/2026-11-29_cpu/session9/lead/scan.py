# ruff: noqa: E501, E701, E702
"""scan.py CAPTURE.pt ...: the real frame's delete vote (heading in degrees; the camera is 30 degrees right of the road,
so the road's heading is about -30) for coherence thresholds, windows and spreads around the defaults (0.9, 7, 1.0),
from the inputs capture.py saved; coherence 0 is the vote without the filter."""
import itertools
import math
import sys

import torch

from sdn3d.editing.photo.road import FORWARD_SNAP_DEG, image_vanishing_point
from sdn3d.image_ops import dilate_square

for cap in sys.argv[1:]:
    g = torch.load(cap, weights_only=False)
    removed, objects_px, K = g["removed"], g["objects_px"], g["K"]
    ys, xs = removed.nonzero(as_tuple=True)
    extent = max(int(ys.max() - ys.min()), int(xs.max() - xs.min()))
    region = dilate_square(removed, max(2 * extent, 20)) & ~dilate_square(objects_px | removed, 2)  # as removal_vanishing_point
    print(cap)
    for c in (0.0, 0.8, 0.85, 0.9, 0.95):
        cells = []
        for w, s in itertools.product((5, 7, 9), (0.5, 1.0, 2.0)):
            u, _ = image_vanishing_point(g["image"], region, K, coherence=c, window=w, spread_deg=s, forward_snap_deg=FORWARD_SNAP_DEG)
            cells.append(f"w{w}/s{s}:{math.degrees(math.atan((u - float(K[0, 2])) / float(K[0, 0]))):+.1f}")
        print(f" coherence {c}: " + " ".join(cells))
