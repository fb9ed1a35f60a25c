# ruff: noqa: E501
"""fit_cues.py TREE CACHE OUT.json [SECOND]: per predicted vehicle proposal with a fit, in the de-rendered scenes of
CACHE (dcache.py / dbench.py's cache of a Table 1 tree, main's de-render, the proposals' fit on), the cues the
test-time fit gives, and the proposal's label by the ground-truth instance map (an ORACLE, used only to label):
'merge' = the proposal holds >= 25 % of each of two true cars (Car / Van over the 64 px filter, splits.py's rule),
else 'single'. Cues: the fit's silhouette IoU (the record), the share of the mask outside the fitted silhouette
('unexpl') and its largest 8-connected part ('unexpl_cc'), the share of the mask's columns where the silhouette has
no pixel ('cols_out'), the mask's box width over the silhouette's ('wratio'), the fitted (l, w) over the template's
typical ones ('l_ratio', 'w_ratio'). SECOND=1: also fit a second car to the largest unexplained part (>= 64 px;
the proposals' fit, started from the first car's fitted pose) and record its fit IoU ('iou2'), the silhouette
union's IoU with the mask against the first's ('union_iou', 'iou1_mask'), and the two footprints' overlap. 'unexpl_open(_px)': the unexplained pixels left by a 3x3 opening (no thin rim).
Session 28 merge40."""
import glob
import json
import sys

import numpy as np
import scipy.ndimage as ndi
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.evaluation.proposal_recall import min_pixels_at
from sdn3d.geometric.fit import FitSettings
from sdn3d.labels import INSTANCE_DIVISOR, VEHICLE_CLASS_NAMES
from sdn3d.math3d.transforms import convex_overlap, ground_footprints
from sdn3d.meshes import TEMPLATE_DIMENSIONS
from sdn3d.meshes.bank import default_bank
from sdn3d.proposal_fit import fit_proposals, fitted_silhouettes

tree, cache, out = sys.argv[1:4]
second = len(sys.argv) > 4 and sys.argv[4] == "1"
torch.set_num_threads(1)
records = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}
names = default_bank().names
typical = torch.tensor([TEMPLATE_DIMENSIONS.get(n, (float("nan"),) * 3) for n in names])
rows_out = []
THINGS = None
for p in sorted(glob.glob(f"{cache}/*.pt")):
    s = torch.load(p, weights_only=False)
    if s.meta.get("proposals") != "semantic" or "fits" not in s.meta:
        continue
    rec = records[s.meta["source"]]
    if THINGS is None:
        THINGS = {c.id for c in s.class_list if c.has_instances and c.name.lower() in VEHICLE_CLASS_NAMES}
    intr = s.intrinsics
    w, h = intr.width, intr.height
    gi = ground_truth(rec, (w, h)).instances
    o = s.objects
    ids = o.instance_id
    fits = {f["id"]: f for f in s.meta["fits"]}
    gids = [int(g) for g in gi.unique() if g >= INSTANCE_DIVISOR and int(g) // INSTANCE_DIVISOR in THINGS]
    cars = {g: gi == g for g in gids if int((gi == g).sum()) > min_pixels_at(w, h)}
    geometry = (o.template_id, o.dims, o.ry, o.location, o.phi)
    fitted = [k for k, i in enumerate(ids.tolist()) if i in fits and fits[i]["fit_iou"] is not None]
    if not fitted:
        continue
    rows = torch.tensor(fitted)
    sil = fitted_silhouettes(intr, geometry, rows)
    for j, k in enumerate(fitted):
        m = o.mask[k]
        area = int(m.sum())
        on = sorted(((int((m & cm).sum()) / int(cm.sum()), int((m & cm).sum()), g) for g, cm in cars.items()), reverse=True)
        held = [g for share, _, g in on if share >= 0.25]
        main_px = max((px for _, px, _ in on), default=0)
        label = "merge" if len(held) >= 2 else "single"
        S = sil[j]
        un = m & ~S
        lab, n = ndi.label(un.numpy(), structure=np.ones((3, 3)))
        cc = np.bincount(lab.ravel())[1:].max() if n else 0
        core = ndi.binary_erosion(un.numpy(), structure=np.ones((3, 3)))  # a rim of 1-2 px erodes away, a car part stays
        core = ndi.binary_dilation(core, structure=np.ones((3, 3))) & un.numpy()  # opening
        mcols, scols = m.any(0), S.any(0)
        cols_out = float((mcols & ~scols).sum()) / max(int(mcols.sum()), 1)
        mw = int(mcols.nonzero().max() - mcols.nonzero().min() + 1)
        sw = int(scols.nonzero().max() - scols.nonzero().min() + 1) if scols.any() else 0
        t = int(o.template_id[k])
        d = o.dims[k].float()
        second_px = sorted((px for _, px, _ in on), reverse=True)[1] if len(on) > 1 else 0
        r = {"key": s.meta["source"], "id": int(ids[k]), "area": area, "label": label, "held": held,
             "held_area": [int(cars[g].sum()) for g in held], "second_share_px": second_px / max(area, 1),
             "main_share_px": main_px / max(area, 1), "iou": fits[int(ids[k])]["fit_iou"],
             "unexpl": int(un.sum()) / area, "unexpl_cc": float(cc) / area, "unexpl_cc_px": int(cc),
             "unexpl_open_px": int(core.sum()), "unexpl_open": float(core.sum()) / area,
             "cols_out": cols_out, "wratio": mw / max(sw, 1),
             "l_ratio": float(d[0] / typical[t, 0]), "w_ratio": float(d[2] / typical[t, 2]),
             "dist": float(o.location[k].norm()), "template": names[t]}
        if second and cc >= 64:
            part = torch.from_numpy(lab == (np.bincount(lab.ravel())[1:].argmax() + 1))
            masks2 = torch.stack([m & ~part, part])
            ids2 = torch.tensor([ids[k], ids[k] + 500])
            g2 = [torch.stack([g[k], g[k]]) for g in geometry]
            g2[3][1] = g2[3][1] * 1.3  # the second car starts behind the first: the first hides it
            g2 = tuple(g2)
            geo2, recs2, _ = fit_proposals(intr, masks2, ids2, torch.tensor([1]), g2, FitSettings())
            r["iou2"] = recs2[0].iou
            s2 = fitted_silhouettes(intr, geo2, torch.tensor([1]))[0]
            r["iou1_mask"] = float((S & m).sum() / (S | m).sum())
            U = S | s2
            r["union_iou"] = float((U & m).sum() / (U | m).sum())
            feet = ground_footprints(torch.stack([o.dims[k], geo2[1][1]]), torch.stack([o.ry[k], geo2[2][1]]),
                                     torch.stack([o.location[k], geo2[3][1]]))
            a2 = min(float(o.dims[k, 0] * o.dims[k, 2]), float(geo2[1][1, 0] * geo2[1][1, 2]))
            r["feet_overlap"] = convex_overlap(feet[0], feet[1]) / a2
            r["dist2"] = float(geo2[3][1].norm())
        rows_out.append(r)
json.dump(rows_out, open(out, "w"), indent=0)
print(out, len(rows_out), "proposals", sum(r["label"] == "merge" for r in rows_out), "merges")
