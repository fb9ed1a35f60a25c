# ruff: noqa: E501, E701, E702
"""readings.py LABEL TREE CAPTURE_DIR [...] (pairs of TREE CAPTURE_DIR): the lamp cue's verdict on the end, per reading,
from capture.py's captures alone (no fit): each fitted vehicle matched to the ground-truth car of largest mask IoU
(>= 0.3; the truth an oracle, for scoring only) and the lamps' evidence (lamps.evidence_of of the captured reading) at
the true local orientation: right (> 0), wrong (< 0) or abstaining, by reading and by the truth's view (side: |sin
alpha| < 0.3). Compares readings of two codes' captures without refitting."""
import glob
import math
import sys
from collections import defaultdict

import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.facing import FRONT_KEYS
from sdn3d.geometric.lamps import evidence_of

label, pairs = sys.argv[1], sys.argv[2:]
tab = defaultdict(lambda: [0, 0, 0])
for tree, cap in zip(pairs[::2], pairs[1::2], strict=True):
    records = index_records(read_frames(tree))
    for f in sorted(glob.glob(f"{cap}/*.pt")):
        c = torch.load(f, weights_only=False)
        _, w, var, fr = c["source"].split("/")
        truth = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects
        app = c["appearance"]; v = app.values
        for r in c["rows"].tolist():
            P = c["masks"][r]
            inter = (P[None] & truth.mask).flatten(1).sum(1).float(); uni = (P[None] | truth.mask).flatten(1).sum(1).float()
            iou = inter / uni.clamp_min(1); t = int(iou.argmax())
            if float(iou[t]) < 0.3 or int(truth.template_id[t]) < 0 or not bool(app.has[r]): continue
            alpha = float(truth.ry[t]) - float(v["ray"][r])
            front = tuple(v[k][r:r + 1] for k in FRONT_KEYS)
            ev = float(evidence_of(v["lamp_present"][r:r + 1].bool(), v["lamp_usable"][r:r + 1].bool(), v["lamp_offset"][r:r + 1],
                                   torch.tensor([[alpha]], dtype=v["lamp_offset"].dtype), app.cue, front=(front[0].bool(), front[1].bool(), front[2])))
            p, u = bool(v["lamp_present"][r]), bool(v["lamp_usable"][r])
            if u: kind = "red present" if p else "red absent"
            elif bool(front[1]): kind = "red body, white present" if bool(front[0]) else "red body, white absent"
            else: kind = "no reading (red present, unusable)" if p else "no reading (small)"
            view = "side" if abs(math.sin(alpha)) < 0.3 else ("back" if math.sin(alpha) < 0 else "front")
            for k in (f"{kind} | {view}", "all"):
                tab[k][0 if ev > 1e-6 else 1 if ev < -1e-6 else 2] += 1
print(f"== {label}: the lamps' verdict at the truth's end: right / wrong / abstains")
for k in sorted(tab):
    r, w_, z = tab[k]; print(f"  {k:50} {r:4d} {w_:4d} {z:4d}")
