# ruff: noqa: INP001, E501
"""fitdiag.py SCRIPT ARGS... | -m MODULE ARGS...: runs SCRIPT (benchmarks/pose_table.py) or MODULE (sdn3d.cli.bench) with the proposals' fit given one input of the
ground truth's (an oracle, for diagnosis), for each proposal whose mask overlaps a ground-truth car or van at IoU
>= 0.3 (the best one). MODE=class: its class name (Car / Van: the templates it may take); MODE=start: its true
template, dimensions, yaw and location as the branch's prediction the fit starts from (the prediction and its flip
are two of the fit's hypotheses, so the truth competes with the others); MODE=both. Not an oracle: MODE=grabcut, each
fitted proposal's mask as the fit reads it is first sharpened by GrabCut on the image (its 2-px core sure
foreground, the rest of it probable foreground, a ring of 4 px probable background, the rest of a window half its
size around sure background; run at twice the size, the largest piece, holes filled); the scene keeps the
proposal's mask. Session 37."""
import os
import runpy
import sys

import cv2
import numpy as np
import torch
import torch.nn.functional as F

import sdn3d.data.scene_gt as sg
import sdn3d.derender as dr
from sdn3d.box_masks import _as_uint8, _grabcut, _largest_filled

MODE = os.environ["MODE"]
LAST = {}
_scene_from_frame, _fit_proposals, _derender = sg.scene_from_frame, dr.fit_proposals, dr.derender
COUNT = {"rows": 0, "matched": 0}


def _remember(record, image_size=None, code_dim=None, **kw):
    scene = _scene_from_frame(record, image_size, **({"code_dim": code_dim} if code_dim is not None else {}), **kw)
    LAST["truth"] = scene
    return scene


def _derender_kept(image, *args, **kw):
    LAST["image"] = image
    return _derender(image, *args, **kw)


def sharpened(image, mask):
    """``(H, W)`` bool: ``mask`` sharpened by GrabCut on ``image`` (the module doc's MODE=grabcut)."""
    m = mask[None, None].float()
    core = (-F.max_pool2d(-m, 5, 1, 2))[0, 0] > 0
    ring = F.max_pool2d(m, 9, 1, 4)[0, 0] > 0
    ys, xs = ring.nonzero(as_tuple=True)
    h, w = mask.shape
    y0, y1, x0, x1 = int(ys.min()), int(ys.max()) + 1, int(xs.min()), int(xs.max()) + 1
    gy, gx = max(4, (y1 - y0) // 2), max(4, (x1 - x0) // 2)
    wy0, wy1, wx0, wx1 = max(0, y0 - gy), min(h, y1 + gy), max(0, x0 - gx), min(w, x1 + gx)
    seed = np.full((wy1 - wy0, wx1 - wx0), cv2.GC_BGD, np.uint8)
    seed[ring[wy0:wy1, wx0:wx1].numpy()] = cv2.GC_PR_BGD
    seed[mask[wy0:wy1, wx0:wx1].numpy()] = cv2.GC_PR_FGD
    seed[core[wy0:wy1, wx0:wx1].numpy()] = cv2.GC_FGD
    fg = _largest_filled(_grabcut(_as_uint8(image)[wy0:wy1, wx0:wx1], seed, 5, 2))
    out = torch.zeros_like(mask)
    out[wy0:wy1, wx0:wx1] = torch.from_numpy(fg.astype(bool))
    return out if int(out.sum()) >= 0.5 * int(mask.sum()) else mask


def _fit(intr, masks, ids, rows, geometry, settings, appearance=None, unsure=None, classes=None, unsure_pixels=None):
    if MODE == "grabcut":
        masks = masks.clone()
        for r in rows.tolist():
            if bool(masks[r].any()):
                masks[r] = sharpened(LAST["image"].cpu(), masks[r])
                COUNT["matched"] += 1
        COUNT["rows"] += len(rows)
        return _fit_proposals(intr, masks, ids, rows, geometry, settings, appearance, unsure, classes, unsure_pixels)
    truth = LAST["truth"].objects
    vehicle = torch.isin(truth.instance_id // 1000, torch.tensor([12, 13])) & truth.has_geometry
    pm, tm = masks[rows].flatten(1).float(), truth.mask.flatten(1).float()
    inter = pm @ tm.T
    iou = inter / (pm.sum(1, keepdim=True) + tm.sum(1)[None] - inter).clamp_min(1)
    iou[:, ~vehicle] = 0
    best, idx = iou.max(1) if len(tm) else (torch.zeros(len(rows)), torch.zeros(len(rows), dtype=torch.long))
    COUNT["rows"] += len(rows)
    classes = list(classes) if classes is not None else [None] * len(ids)
    geometry = tuple(g.clone() for g in geometry)
    for k, r in enumerate(rows.tolist()):
        if float(best[k]) < 0.3:
            continue
        COUNT["matched"] += 1
        t = int(idx[k])
        if MODE in ("class", "both"):
            classes[r] = "Car" if int(truth.instance_id[t]) // 1000 == 12 else "Van"
        if MODE in ("start", "both"):
            for g, name in zip(geometry, ("template_id", "dims", "ry", "location", "phi"), strict=True):
                g[r] = getattr(truth, name)[t].to(g.dtype)
    return _fit_proposals(intr, masks, ids, rows, geometry, settings, appearance, unsure, classes, unsure_pixels)


sg.scene_from_frame = _remember
dr.fit_proposals = _fit
dr.derender = _derender_kept
try:
    if sys.argv[1] == "-m":  # a module (python -m sdn3d.cli.bench ...)
        sys.argv = sys.argv[2:]
        runpy.run_module(sys.argv[0], run_name="__main__", alter_sys=True)
    else:
        sys.argv = sys.argv[1:]
        runpy.run_path(sys.argv[0], run_name="__main__")
finally:
    print(f"fitdiag {MODE}: {COUNT['matched']} of {COUNT['rows']} fitted proposals given the truth's input (grabcut: sharpened)", file=sys.stderr)
