# ruff: noqa: E501, E701, E702, E731, B023, B905
"""parts.py RAW.pt... : how often a proposal of a grouping (GROUPING_DEFAULTS of the installed sdn3d, as
SemanticPredictor groups; GROUPING='{json}' overrides them, e.g. main's: '{"part_separation": null}') spans spatially disconnected pixels, and what the pieces are.
RAW.pt: session 19 inst's raw.py outputs (a Table 1 tree's source frames at 312x96, the demo's weights).

For every proposal, its pixels' 8-connected components; the largest is the proposal's main part, every other one a
piece. Each piece is described by: its area (all pixels; "sure": the arg-max's Car/Van pixels, what min_area counts),
what it lies on (the ground truth, an oracle for scoring only: the Car/Van instance holding most of its pixels, else
"background"), compared with the main part's: same_car (the piece is more of the main part's car: a car cut by
something thin), other_car (another car), background; the chessboard gap to the main part (pixels between them); the
distance between the piece's mean vote (pixel + offset) and the main part's, in pixels and in the pooled vote SD;
the centre heatmap's maximum inside the piece. Prints counts by kind and size, and the gap / vote-distance quantiles;
JSON=path writes every piece."""
import json
import os
import sys

import numpy as np
import torch
from scipy import ndimage

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

g = {**GROUPING_DEFAULTS, **json.loads(os.environ.get("GROUPING", "{}"))}
rows = []
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]
    for key, fr in raw["frames"].items():
        prob = fr["logits"].float().softmax(0)[None]; center = fr["center"][None]; offset = fr["offset"][None]
        inst, _ = group_vehicles(prob.argmax(1), prob, center, offset, things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                                 nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                                 part_separation=g.get("part_separation"))
        inst = inst[0].numpy(); sure = np.isin(prob.argmax(1)[0].numpy(), things)
        gi = fr["gt_instances"].numpy(); gcar = (gi >= INSTANCE_DIVISOR) & np.isin(gi // INSTANCE_DIVISOR, things)
        h, w = inst.shape; vv, uu = np.mgrid[0:h, 0:w]
        vu = uu + fr["offset"][0].numpy(); vvv = vv + fr["offset"][1].numpy(); heat = fr["center"][0].numpy()
        for p in np.unique(inst[inst > 0]):
            comp, n = ndimage.label(inst == p, structure=np.ones((3, 3)))
            if n < 2: continue
            areas = np.bincount(comp.ravel())[1:]; main = int(areas.argmax()) + 1

            def owner(m):
                ids, cnt = np.unique(np.where(gcar[m], gi[m], 0), return_counts=True)
                return int(ids[cnt.argmax()])

            mm = comp == main; mown = owner(mm)
            mu, mv = vu[mm].mean(), vvv[mm].mean(); msd2 = ((vu[mm] - mu) ** 2 + (vvv[mm] - mv) ** 2).mean() / 2
            dist = ndimage.distance_transform_cdt(~mm, metric="chessboard")
            for c in range(1, n + 1):
                if c == main: continue
                m = comp == c; own = owner(m)
                kind = "background" if own == 0 else ("same_car" if own == mown else "other_car")
                cu, cv = vu[m].mean(), vvv[m].mean(); sd2 = ((vu[m] - cu) ** 2 + (vvv[m] - cv) ** 2).mean() / 2
                dvote = float(np.hypot(cu - mu, cv - mv)); pooled = float(np.sqrt((sd2 + msd2) / 2))
                rows.append({"tree": raw["tree"], "key": str(key), "proposal": int(p), "kind": kind, "area": int(m.sum()), "sure": int((m & sure).sum()),
                             "main_area": int(mm.sum()), "main_on": "car" if mown else "background", "gap": int(dist[m].min()) - 1, "vote_dist": dvote,
                             "vote_sep": dvote / max(pooled, 0.5), "heat_max": float(heat[m].max())})
props = 0
print(f"grouping {g}")
print(f"{len(rows)} pieces (components other than their proposal's largest)")
for kind in ("same_car", "other_car", "background"):
    r = [x for x in rows if x["kind"] == kind]
    for lo, hi, name in ((0, g["min_area"], f"sure < {g['min_area']}"), (g["min_area"], 10 ** 9, f"sure >= {g['min_area']}")):
        s = [x for x in r if lo <= x["sure"] < hi]
        if not s: print(f"  {kind:10s} {name:12s}: 0"); continue
        q = lambda k: np.percentile([x[k] for x in s], [10, 50, 90]).round(1).tolist()
        print(f"  {kind:10s} {name:12s}: {len(s):4d} pieces, area {sum(x['area'] for x in s):6d} px; gap p10/50/90 {q('gap')}, vote dist {q('vote_dist')} px, vote sep {q('vote_sep')} SD, heat max {q('heat_max')}")
for kind in ("same_car", "other_car", "background"):
    s = [x for x in rows if x["kind"] == kind and x["sure"] >= g["min_area"]]
    if s: print(f"{kind} (sure >= min_area) gap histogram:", dict(zip(*np.unique(np.minimum([x['gap'] for x in s], 10), return_counts=True))))
if os.environ.get("JSON"):
    with open(os.environ["JSON"], "w") as f: json.dump(rows, f)
