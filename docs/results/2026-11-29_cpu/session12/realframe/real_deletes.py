# ruff: noqa: E501
"""real_deletes.py PROBE_DIR [PROBE_DIR ...]: the real frame's deletes (probe.py's 12001_deleted / 12002_deleted .npz)
measured: the delete region (source code fill) against the road around it (its pixels 8 to 40 pixels from the region,
on no car, within 12 CIE Lab chroma of the road's colour, road.road_colours): mean absolute luma Laplacian of each
(road._luma_laplacian, the texture measure of issue 41) and their ratio; and the share of the region's lower half
(below its middle row: the ground the car stood on and the lane in front) whose Lab chroma is more than 12 from the
road's (a verge's or grass colour carried in)."""

from __future__ import annotations

import sys

import numpy as np
import torch

from sdn3d.editing.photo.road import _luma_laplacian, road_colours, road_lab
from sdn3d.editing.photo.settings import FILL, INPUT
from sdn3d.image_ops import dilate_square


def measure(path: str) -> dict:
    z = np.load(path)
    image = torch.from_numpy(z["edited"]).permute(2, 0, 1).float() / 255
    source = torch.from_numpy(z["source"])
    hole = source == FILL
    ring = dilate_square(hole, 40) & ~dilate_square(hole, 8) & (source == INPUT)
    road = road_colours(image, ring)
    lab = road_lab(image.permute(1, 2, 0).reshape(-1, 3)).view(*hole.shape, 3)
    near = (lab[..., 1:] - road[1:]).norm(dim=-1) < 12
    lap = _luma_laplacian(image)
    around = ring & near
    rows = hole.any(1).nonzero().flatten()
    mid = int(rows[len(rows) // 2])
    lower = hole.clone()
    lower[:mid] = False
    return {"hole_px": int(hole.sum()), "lap_hole": float(lap[hole].mean()), "lap_road": float(lap[around].mean()),
            "ratio": float(lap[hole].mean() / lap[around].mean()), "non_road_lower": float((~near[lower]).double().mean())}


for d in sys.argv[1:]:
    for iid in (12001, 12002):
        m = measure(f"{d}/{iid}_deleted.npz")
        print(f"{d} {iid}: region {m['hole_px']} px, |Laplacian| region {m['lap_hole']:.4f} road {m['lap_road']:.4f} ratio {m['ratio']:.3f}; non-road colour in the region's lower half {100 * m['non_road_lower']:.1f} %")
