# ruff: noqa: E501
"""twofit.py TREE CACHE CUES.json OUT.json: the two-car explanation of every fitted predicted vehicle proposal of
CUES.json (fit_cues.py; >= 128 px) in CACHE: its mask cut in two by 2-means on the pixels' (x, y), each part fitted
as a car (main's fit, FitSettings(), started from the proposal's fitted pose and template, the other part's pixels
counting for neither car nor background, as an occluder's), in one fit call per frame. Records per proposal: the
IoU with the mask of the two fitted silhouettes' union ('iou_two') and of the one fitted car ('iou_one', the
scene's own fit), the parts' fit IoUs ('part_ious'), the parts' footprint overlap over the smaller ('feet_overlap'),
their distances. The label (merge / single) is fit_cues.py's, from the ground truth (an ORACLE, only to label).
Session 28 merge40."""
import glob
import json
import sys

import torch

from sdn3d.geometric.fit import FitRequest, FitSettings, fit_many
from sdn3d.image_ops import mask_boxes
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.math3d.transforms import convex_overlap, ground_footprints
from sdn3d.proposal_fit import apply_proposal_fit, fitted_silhouettes


def two_means(m: torch.Tensor, iters: int = 10) -> torch.Tensor:
    """``(H, W)`` bool: the part of ``m`` nearer the first of two 2-means centres on the pixels' (x, y)."""
    ys, xs = m.nonzero(as_tuple=True)
    p = torch.stack([xs, ys], 1).float()
    c = p[torch.stack([p[:, 0].argmin(), p[:, 0].argmax()])]
    for _ in range(iters):
        a = (p[:, None] - c[None]).square().sum(2).argmin(1)
        c = torch.stack([p[a == k].mean(0) if (a == k).any() else c[k] for k in range(2)])
    part = torch.zeros_like(m)
    part[ys[a == 0], xs[a == 0]] = True
    return part


tree, cache, cues, out = sys.argv[1:5]
torch.set_num_threads(1)
rows = json.load(open(cues))
by_key: dict[str, list[dict]] = {}
for r in rows:
    if r["area"] >= 128:
        by_key.setdefault(r["key"], []).append(r)
settings = FitSettings()
names = {12: "Car", 13: "Van"}
res = []
for p in sorted(glob.glob(f"{cache}/*.pt")):
    s = torch.load(p, weights_only=False)
    if s.meta.get("proposals") != "semantic" or s.meta["source"] not in by_key:
        continue
    o, intr = s.objects, s.intrinsics
    geometry = (o.template_id, o.dims, o.ry, o.location, o.phi)
    ks, masks, ignore = [], [], []
    for r in by_key[s.meta["source"]]:
        k = int((o.instance_id == r["id"]).nonzero()[0])
        m = o.mask[k]
        a = two_means(m)
        b = m & ~a
        if int(a.sum()) < 32 or int(b.sum()) < 32:
            continue
        ks += [k, k]
        masks += [a, b]
        ignore += [b, a]
    if not ks:
        continue
    kk = torch.tensor(ks)
    masks_t, ignore_t = torch.stack(masks), torch.stack(ignore)
    g = tuple(x[kk] for x in geometry)
    req = FitRequest(masks_t, mask_boxes(masks_t).float(), ignore=ignore_t, start_ry=g[2].float(), start_dims=g[1].float(),
                     start_template=g[0], start_location=g[3].float(),
                     classes=[names.get(int(o.instance_id[k]) // INSTANCE_DIVISOR) for k in ks])
    result = fit_many([req], intr, settings=settings)[0]
    rows2 = torch.arange(len(ks))
    ids2 = torch.arange(len(ks)) + 1
    geo2, recs = apply_proposal_fit(result, ids2, rows2, g, settings)
    sil2 = fitted_silhouettes(intr, geo2, rows2)
    sil1 = fitted_silhouettes(intr, geometry, kk[::2])
    for j in range(0, len(ks), 2):
        k = ks[j]
        m = o.mask[k]
        r = next(x for x in by_key[s.meta["source"]] if x["id"] == int(o.instance_id[k]))
        U = sil2[j] | sil2[j + 1]
        S1 = sil1[j // 2]
        feet = ground_footprints(geo2[1][j:j + 2], geo2[2][j:j + 2], geo2[3][j:j + 2])
        small = min(float(geo2[1][j, 0] * geo2[1][j, 2]), float(geo2[1][j + 1, 0] * geo2[1][j + 1, 2]))
        res.append({"key": r["key"], "id": r["id"], "label": r["label"], "area": r["area"],
                    "second_share_px": r["second_share_px"], "main_share_px": r["main_share_px"],
                    "iou_one": float((S1 & m).sum() / (S1 | m).sum()), "iou_two": float((U & m).sum() / (U | m).sum()),
                    "part_ious": [recs[j].iou, recs[j + 1].iou],
                    "feet_overlap": convex_overlap(feet[0], feet[1]) / max(small, 1e-9),
                    "dists": [float(geo2[3][j].norm()), float(geo2[3][j + 1].norm())]})
json.dump(res, open(out, "w"), indent=0)
print(out, len(res), "proposals", sum(r["label"] == "merge" for r in res), "merges")
