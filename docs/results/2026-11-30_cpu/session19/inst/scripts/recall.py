# ruff: noqa: E501, E701, E702
"""recall.py RAW.pt...: proposal recall (sdn3d.evaluation.proposal_recall.match_proposals: annotated Car/Van objects
over the paper's pixel filter at the size, found by a proposal at IoU >= 0.5 and >= 0.3, one proposal per object)
and precision of main's grouping (GROUPING_DEFAULTS with thing_odds and split_separation None) and the branch's
(GROUPING_DEFAULTS), per raw file (raw.py: a tree's Table 1 source frames) and pooled. The ground truth is an oracle
used for scoring only. Beside them the floor of benchmarks/proposal_recall.py: one proposal per 8-connected component of
the arg-max's Car / Van pixels ("components")."""
import os
import sys

import torch
from census import segment
from scipy import ndimage

from sdn3d.evaluation.proposal_recall import match_proposals, min_pixels_at
from sdn3d.semantic.predict import GROUPING_DEFAULTS

ARMS = {"main": {**GROUPING_DEFAULTS, "thing_odds": None, "split_separation": None}, "branch": dict(GROUPING_DEFAULTS),
        "components": None}


def components(fr, things):
    lab = fr["logits"].float().argmax(0).numpy(); out = torch.zeros(lab.shape, dtype=torch.long)
    for c in things:
        comp, _ = ndimage.label(lab == c, structure=[[1, 1, 1]] * 3)
        out[comp > 0] = torch.from_numpy(c * 1000 + comp[comp > 0]).long()
    return out

pooled = {}
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); size = raw["size"]
    for arm, g in ARMS.items():
        for iou in (0.5, 0.3):
            counts = None
            for fr in raw["frames"].values():
                inst = segment(fr, raw["things"], g)[0] if g is not None else components(fr, raw["things"])
                c = match_proposals(inst[None], fr["gt_instances"][None], raw["things"], min_pixels_at(*size), iou)
                counts = c if counts is None else counts + c
            s = counts.summary(); pooled[(arm, iou)] = pooled.get((arm, iou), type(counts)()) + counts
            print(f"{os.path.basename(path):16s} {arm:10s} IoU>={iou}: recall {s['recall']:.3f} ({sum(counts.found.values())}/{s['objects']}), precision {s['precision']:.3f} ({counts.true_proposals}/{s['proposals']} proposals)")
if len(sys.argv) > 2:
    for (arm, iou), counts in pooled.items():
        s = counts.summary()
        print(f"{'pooled':16s} {arm:10s} IoU>={iou}: recall {s['recall']:.3f} ({sum(counts.found.values())}/{s['objects']}), precision {s['precision']:.3f} ({counts.true_proposals}/{s['proposals']} proposals)")
