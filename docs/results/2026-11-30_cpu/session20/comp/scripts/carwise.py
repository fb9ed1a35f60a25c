# ruff: noqa: E501, E701, E702
"""carwise.py RAW.pt: every annotated Car/Van over the paper's pixel filter (ground truth, an oracle for scoring only)
whose best proposal IoU crosses 0.5 or 0.3 between main's grouping (part_separation None) and the branch's
(GROUPING_DEFAULTS): frame, car id, area, best IoU under each, and the number of proposals in the frame."""
import sys

import torch

from sdn3d.evaluation.proposal_recall import min_pixels_at
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS


def group(fr, things, part):
    g = GROUPING_DEFAULTS; prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                          nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"], part_separation=part)[0][0]


def best(inst, m):
    ious = [int((inst == p)[m].sum()) / int(((inst == p) | m).sum()) for p in inst.unique().tolist() if p > 0]
    return max(ious, default=0.0)


raw = torch.load(sys.argv[1], weights_only=False); things = raw["things"]
for key, fr in raw["frames"].items():
    a, b = group(fr, things, None), group(fr, things, GROUPING_DEFAULTS["part_separation"])
    gi = fr["gt_instances"]
    for i in gi.unique().tolist():
        if i < INSTANCE_DIVISOR or i // INSTANCE_DIVISOR not in things: continue
        m = gi == i
        if int(m.sum()) <= min_pixels_at(*raw["size"]): continue
        ia, ib = best(a, m), best(b, m)
        if (ia >= 0.5) != (ib >= 0.5) or (ia >= 0.3) != (ib >= 0.3):
            print(f"{key} car {i} area {int(m.sum())}: main {ia:.3f} branch {ib:.3f}; proposals main {a.unique().numel() - 1} branch {b.unique().numel() - 1}")
