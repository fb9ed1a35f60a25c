# ruff: noqa: E501, INP001
"""real_measure.py PROBE_DIR [PROBE_DIR ...]: the real frame's deletes (session 12's realframe/probe.py outputs,
12001_deleted.npz and 12002_deleted.npz: the edited picture and its source map) measured on the delete region (source
code fill):

- texture: mean absolute luma Laplacian (road._luma_laplacian, issue 41's measure) of the region over that of the road
  around it (its pixels 8 to 40 px from the region, drawn from the input, within 12 Lab chroma of the road's colour,
  road.road_colours of that ring); the goal is a ratio within 10 % of 1;
- verge share: the share of the region's pixels whose colour is no road (road.verge_like: Lab chroma farther than 12
  from both the road's and grey, min_light 0: the verge's grass colour), over the whole region and over its lower half (rows below
  its middle row: the ground the car stood on and in front of it);
- residual darkening: over the region's lower half, row by row, 1 - (mean luma of its road pixels) / (median luma of the
  ring's road pixels on the nearest rows that have some), averaged over rows weighted by pixels (0: as light as the
  road around; the car's shadow left behind shows as a positive figure).
"""

from __future__ import annotations

import sys

import numpy as np
import torch

from sdn3d.editing.photo.road import _luma_laplacian, road_colours, road_lab, verge_like
from sdn3d.editing.photo.settings import FILL, INPUT
from sdn3d.image_ops import dilate_square, luminance


def measure(path: str) -> dict:
    z = np.load(path)
    image = torch.from_numpy(z["edited"]).permute(2, 0, 1).float() / 255
    source = torch.from_numpy(z["source"])
    region = source == FILL
    ring = dilate_square(region, 40) & ~dilate_square(region, 8) & (source == INPUT)
    road = road_colours(image, ring)
    lab = road_lab(image.permute(1, 2, 0).reshape(-1, 3)).view(*region.shape, 3)
    near = (lab[..., 1:] - road[1:]).norm(dim=-1) < 12
    lap = _luma_laplacian(image)
    around = ring & near
    rows = region.any(1).nonzero().flatten()
    lower = region.clone()
    lower[: int(rows[len(rows) // 2])] = False
    verge = torch.zeros_like(region)
    verge[region] = verge_like(image[:, region], road, min_light=0.0)
    luma = luminance(image.permute(1, 2, 0).reshape(-1, 3)).view(region.shape)
    ref_rows = around.any(1).nonzero().flatten()
    dark, weight = 0.0, 0
    for r in lower.any(1).nonzero().flatten().tolist():
        px = lower[r] & ~verge[r]
        if not bool(px.any()):
            continue
        nearest = ref_rows[(ref_rows - r).abs().argsort()[:3]]
        ref = float(luma[nearest][around[nearest]].median())
        dark += (1 - float(luma[r][px].mean()) / ref) * int(px.sum())
        weight += int(px.sum())
    return {"px": int(region.sum()), "ratio": float(lap[region].mean() / lap[around].mean()),
            "verge": float(verge[region].double().mean()), "verge_lower": float(verge[lower].double().mean()),
            "darkening": dark / max(weight, 1)}


print("| run | car | region px | texture ratio (region / road around) | verge share, region | verge share, lower half | residual darkening, lower half |")
print("|---|---|---|---|---|---|---|")
for d in sys.argv[1:]:
    for iid in (12001, 12002):
        m = measure(f"{d}/{iid}_deleted.npz")
        print(f"| {d} | {iid} | {m['px']} | {m['ratio']:.3f} | {100 * m['verge']:.1f} % | {100 * m['verge_lower']:.1f} % | {100 * m['darkening']:+.1f} % |")
