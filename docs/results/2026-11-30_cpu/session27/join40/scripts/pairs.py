"""pairs.py OUT.json CACHE:RAW...: every pair of touching fitted vehicle proposals in de-rendered scenes, with the
overlap of their fitted ground footprints and a truth label (session 27 join40, step 1).

CACHE: a de-render cache directory of dbench.py (one SceneCode per file; only the scenes with predicted proposals,
``meta['proposals'] == 'semantic'``, are read); RAW: frag40's raw.py file of the same tree (its ``gt_instances`` per
frame key: the ground-truth instance map at 312x96, an oracle used only to label pairs).

Per pair of objects with a fitted 3D box (``meta['fits']`` lists them) whose masks lie within GAP px (8-neighbour
dilation; 1 = the masks touch): ``gap`` (smallest dilation radius at which they meet), the footprints' (bird's-eye
rectangles of the fitted boxes on the road: x/z centre, yaw, length x width) IoU and intersection over the smaller
footprint (``ios``), the centres' distance, each one's distance, area, fit IoU, and the truth:

- ``same``: both proposals lie for >= 50 % of their pixels on one true Car/Van (two fragments of one car);
- ``two``: each lies for >= 50 % on a different true Car/Van (two cars);
- ``other``: anything else (a proposal mostly on background or on no one car).

Run: PYTHONPATH=<code>/src python pairs.py out.json /tmp/s26data/frag40/t1/cache31main:/tmp/s26data/frag40/raw/raw31.pt
"""
import glob
import json
import os
import sys

import torch

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.math3d.transforms import bottom_to_center, box_corners

GAP = 4
VEHICLES = (12, 13)  # Car, Van (vkitti)


def footprint(dims: torch.Tensor, ry: torch.Tensor, location: torch.Tensor) -> list[tuple[float, float]]:
    """The fitted box's bottom face as (x, z) points (counter-clockwise or not: area() takes the sign off)."""
    c = box_corners(dims[None].double(), ry[None].double(), bottom_to_center(location[None].double(),
                                                                            dims[None, 1].double()))[0]
    return [(float(c[i, 0]), float(c[i, 2])) for i in range(4)]


def area(poly: list[tuple[float, float]]) -> float:
    return abs(sum(poly[i][0] * poly[i - 1][1] - poly[i - 1][0] * poly[i][1] for i in range(len(poly)))) / 2


def orient(poly: list[tuple[float, float]]) -> list[tuple[float, float]]:
    s = sum(poly[i][0] * poly[i - 1][1] - poly[i - 1][0] * poly[i][1] for i in range(len(poly)))
    return poly if s < 0 else poly[::-1]  # counter-clockwise in (x, z)


def clip(subject: list, clipper: list) -> list:
    """Sutherland-Hodgman: the part of convex ``subject`` inside convex ``clipper`` (both counter-clockwise)."""
    out = subject
    for i in range(len(clipper)):
        a, b = clipper[i - 1], clipper[i]
        inp, out = out, []
        if not inp:
            break

        def inside(p, a=a, b=b):
            return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0

        for j in range(len(inp)):
            p, q = inp[j - 1], inp[j]
            if inside(q):
                if not inside(p):
                    out.append(cross(p, q, a, b))
                out.append(q)
            elif inside(p):
                out.append(cross(p, q, a, b))
    return out


def cross(p, q, a, b):
    x1, y1, x2, y2, x3, y3, x4, y4 = *p, *q, *a, *b
    d = (x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4)
    t = ((x1 - x3) * (y3 - y4) - (y1 - y3) * (x3 - x4)) / d
    return (x1 + t * (x2 - x1), y1 + t * (y2 - y1))


def overlap(fa: list, fb: list) -> tuple[float, float]:
    fa, fb = orient(fa), orient(fb)
    # clip() keeps the left side of each edge: counter-clockwise in a right-handed frame; (x, z) seen from above
    # with y down is left-handed, so orient() makes the signed area negative; either way test both orders.
    inter = clip(fa, fb)
    if len(inter) < 3:
        inter = clip(fa[::-1], fb[::-1])
    i = area(inter) if len(inter) >= 3 else 0.0
    a, b = area(fa), area(fb)
    return i / (a + b - i), i / min(a, b)


def gaps(masks: torch.Tensor) -> torch.Tensor:
    """``(N, N)`` smallest dilation radius (1..GAP) at which masks i and j meet; GAP + 1: farther."""
    n = len(masks)
    out = torch.full((n, n), GAP + 1)
    m = masks[:, None].float()
    for r in range(GAP, 0, -1):
        grown = torch.nn.functional.max_pool2d(m, 2 * r + 1, 1, r)[:, 0] > 0  # (N, H, W)
        meet = (grown.flatten(1).float() @ masks.flatten(1).float().T) > 0
        out[meet] = r
    return out


def truth(mask: torch.Tensor, gi: torch.Tensor) -> tuple[int, float]:
    ids, counts = gi[mask].unique(return_counts=True)
    best, frac = 0, 0.0
    for i, c in zip(ids.tolist(), counts.tolist(), strict=True):
        if i >= INSTANCE_DIVISOR and i // INSTANCE_DIVISOR in VEHICLES and c / int(mask.sum()) > frac:
            best, frac = i, c / int(mask.sum())
    return best, frac


def main() -> None:
    rows = []
    for arg in sys.argv[2:]:
        cache, rawp = arg.split(":")
        raw = torch.load(rawp, weights_only=False)
        tree = os.path.basename(rawp)[3:-3]
        for p in sorted(glob.glob(f"{cache}/*.pt")):
            s = torch.load(p, weights_only=False)
            if s.meta.get("proposals") != "semantic" or "fits" not in s.meta:
                continue
            key = s.meta["source"]
            gi = raw["frames"][key]["gt_instances"]
            o = s.objects
            fits = {f["id"]: f for f in s.meta["fits"]}
            rows_ = [k for k, i in enumerate(o.instance_id.tolist()) if i in fits and int(o.template_id[k]) >= 0]
            if len(rows_) < 2:
                continue
            masks = o.mask[rows_]
            g = gaps(masks)
            fp = [footprint(o.dims[k], o.ry[k], o.location[k]) for k in rows_]
            tr = [truth(masks[a], gi) for a in range(len(rows_))]
            for a in range(len(rows_)):
                for b in range(a + 1, len(rows_)):
                    if int(g[a, b]) > GAP:
                        continue
                    ka, kb = rows_[a], rows_[b]
                    iou, ios = overlap(fp[a], fp[b])
                    (ta, fa), (tb, fb) = tr[a], tr[b]
                    label = ("same" if ta and ta == tb and fa >= 0.5 and fb >= 0.5 else
                             "two" if ta and tb and ta != tb and fa >= 0.5 and fb >= 0.5 else "other")
                    la, lb = o.location[ka], o.location[kb]
                    rows.append({
                        "tree": tree, "key": key, "a": int(o.instance_id[ka]), "b": int(o.instance_id[kb]),
                        "gap": int(g[a, b]), "iou": round(iou, 4), "ios": round(ios, 4),
                        "dist": round(float((la[[0, 2]] - lb[[0, 2]]).norm()), 3),
                        "za": round(float(la[2]), 2), "zb": round(float(lb[2]), 2),
                        "area_a": int(masks[a].sum()), "area_b": int(masks[b].sum()),
                        "fit_a": fits[int(o.instance_id[ka])]["fit_iou"],
                        "fit_b": fits[int(o.instance_id[kb])]["fit_iou"],
                        "truth_a": ta, "truth_b": tb, "frac_a": round(fa, 3), "frac_b": round(fb, 3),
                        "label": label})
    with open(sys.argv[1], "w") as f:
        json.dump(rows, f, indent=0)
    print(len(rows), "pairs")


if __name__ == "__main__":
    main()
