# ruff: noqa: B023, E402, E501, E701, E702, E731
"""replay.py TREE CAPTURE_DIR VARIANT [OUT.json]: the captured proposal fits (capture.py) fitted again with this tree's
code and a variant, each fitted vehicle matched to the ground-truth object of largest mask IoU (oracle, for measurement
only): relative distance error, split by whether the mask stops >= 2 px above the car's visible bottom (cut).
Variants: base (the code as it is); oracle_start (the truth's place, size and yaw as the prediction: does the fit stay
there?); band=F (UNSURE_BELOW F); any other NAME=VALUE is a FitSettings field."""
import glob
import json
import sys

import numpy as np
import torch

import sdn3d.proposal_fit as pf
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.image_ops import mask_boxes

tree, cap, variant = sys.argv[1:4]
records = index_records(read_frames(tree))
torch.set_num_threads(1)
kw, band, oracle = {}, None, False
GRAB, START = [], []
for v in variant.split(","):
    if v == "base": continue
    if v == "oracle_start": oracle = True; continue
    k, val = v.split("=")
    if k == "band": band = float(val); continue
    if k == "boxband": band = -float(val); continue
    if k == "grabcut": GRAB.extend(float(t) for t in val.split(":")); continue
    if k == "grabstart": GRAB.extend(float(t) for t in val.split(":")); START.append(True); continue
    kw[k] = type(getattr(FitSettings(), k))(val) if not isinstance(getattr(FitSettings(), k), bool) else val == "true"
settings = FitSettings(**kw)


def grown(image, masks, rows, down, side=0.25):
    """GrabCut from each mask (sure car), the box grown by a quarter of its width on each side and by ``down`` of its
    height below (probable car), off the other masks (sure background)."""
    import cv2

    from sdn3d.box_masks import _as_uint8, _grabcut
    px = _as_uint8(image)
    n, h, w = masks.shape
    out = masks.clone()
    others_all = masks.any(0)
    for r in rows.tolist():
        m = masks[r]
        ys, xs = m.any(1).nonzero().flatten(), m.any(0).nonzero().flatten()
        y0, y1, x0, x1 = int(ys.min()), int(ys.max()) + 1, int(xs.min()), int(xs.max()) + 1
        gx, gy = int(np.ceil(side * (x1 - x0))), int(np.ceil(down * (y1 - y0)))
        bx0, bx1, by1 = max(0, x0 - gx), min(w, x1 + gx), min(h, y1 + gy)
        wx0, wx1, wy0, wy1 = max(0, bx0 - 8), min(w, bx1 + 8), max(0, y0 - 4), min(h, by1 + 6)
        seed = np.full((wy1 - wy0, wx1 - wx0), cv2.GC_PR_BGD, np.uint8)
        seed[y0 - wy0:by1 - wy0, bx0 - wx0:bx1 - wx0] = cv2.GC_PR_FGD
        other = (others_all & ~m).numpy()[wy0:wy1, wx0:wx1]
        seed[other] = cv2.GC_BGD
        seed[m.numpy()[wy0:wy1, wx0:wx1]] = cv2.GC_FGD
        fg = _grabcut(px[wy0:wy1, wx0:wx1], seed, 5, 1).astype(bool)
        new = torch.zeros_like(m)
        new[wy0:wy1, wx0:wx1] = torch.from_numpy(fg)
        out[r] = new | m
    return out


def box_band(masks, fraction):
    """Every mask's box, grown down by fraction of its height, off every mask."""
    n, h, w = masks.shape
    out = torch.zeros_like(masks)
    for i in range(n):
        ys, xs = masks[i].any(1).nonzero().flatten(), masks[i].any(0).nonzero().flatten()
        if not len(ys): continue
        last = int(ys.max()) + int(np.ceil(fraction * (int(ys.max()) - int(ys.min()) + 1)))
        out[i, int(ys.min()):last + 1, int(xs.min()):int(xs.max()) + 1] = True
    return out & ~masks.any(0)
rows_out = []
for f in sorted(glob.glob(cap + "/*.pt")):
    c = torch.load(f, weights_only=False)
    _, w, var, fr = c["source"].split("/")
    gt = scene_from_frame(records[(w, var, int(fr))], (312, 96))
    masks, rows, geometry = c["masks"], c["rows"], c["geometry"]
    unsure = c["unsure"]
    if band is not None and unsure is not None: unsure = pf.unsure_below(masks, band) if band > 0 else box_band(masks, -band)
    gm = gt.objects.mask
    if GRAB and unsure is not None:
        from sdn3d.data.frames import load_frame
        image = load_frame(records[(w, var, int(fr))], (312, 96), semantic=False, instances=False).image
        g2 = grown(image, masks, rows, GRAB[0], GRAB[1] if len(GRAB) > 1 else 0.25)
        if START:  # the loss's masks as they were, the grown pixels unsure, the boxes (road start, window) the grown masks'
            unsure = pf.unsure_below(masks) | (g2 & ~masks.any(0))
            gb = mask_boxes(g2)
            pf.mask_boxes = lambda m, gb=gb, rows=rows: gb[rows] if m.shape[0] == len(rows) else mask_boxes(m)
        else:
            masks = g2
            unsure = pf.unsure_below(masks)
    match = {}
    for r in rows.tolist():
        m = c["masks"][r]
        iou = (gm & m).flatten(1).sum(1).float() / (gm | m).flatten(1).sum(1).float().clamp_min(1)
        g = int(iou.argmax())
        if iou[g] >= 0.2: match[r] = g
    if oracle:
        template, dims, ry, location, phi = (t.clone() for t in geometry)
        for r, g in match.items():
            dims[r], ry[r], location[r] = gt.objects.dims[g].double(), gt.objects.ry[g].double(), gt.objects.location[g].double()
            location[r, 1] = 1.65
        geometry = (template, dims, ry, location, phi)
    extra = {"semantic": c["semantic"]} if "semantic" in pf.fit_proposals.__code__.co_varnames else {}
    geo, recs = pf.fit_proposals(c["intr"], masks, c["ids"], rows, geometry, settings, c["appearance"], unsure, c["classes"], **extra)
    for k, r in enumerate(rows.tolist()):
        if r not in match or recs[k].iou is None: continue
        g = match[r]
        ys, gys = c["masks"][r].any(1).nonzero().flatten(), gm[g].any(1).nonzero().flatten()
        zt, zf = float(gt.objects.location[g, 2]), float(geo[3][r, 2])
        rows_out.append({"key": f"{w}/{var} {fr}", "row": r, "var": var, "cut": int(gys.max() - ys.max()), "z_true": zt, "z_fit": zf,
                         "z_err": (zf - zt) / zt, "scale": float((geo[1][r].float() / gt.objects.dims[g]).log().mean().exp()), "hyp": recs[k].hypothesis})
if len(sys.argv) > 4: json.dump(rows_out, open(sys.argv[4], "w"))
print(variant, tree.split("/")[-1])
for var in sorted({r["var"] for r in rows_out}):
    v = [r for r in rows_out if r["var"] == var]
    for name, sel in (("cut>=2", [r for r in v if r["cut"] >= 2]), ("uncut", [r for r in v if r["cut"] < 2])):
        if not sel: continue
        a = lambda k: np.array([r[k] for r in sel])
        print(f"  {var:6s} {name:7s} n {len(sel):3d}: z err median {np.median(a('z_err')):+.3f} mean|.| {np.abs(a('z_err')).clip(0, 1).mean():.3f}; scale median {np.median(a('scale')):.3f}")
