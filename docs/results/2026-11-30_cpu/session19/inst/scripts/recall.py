# ruff: noqa: E501, E701, E702
"""recall.py RAW.pt...: proposal recall (sdn3d.evaluation.proposal_recall.match_proposals: annotated Car/Van objects
over the paper's pixel filter at the size, found by a proposal at IoU >= 0.5 and >= 0.3, one proposal per object)
and precision of main's grouping (GROUPING_DEFAULTS with thing_odds and split_separation None) and the branch's
(GROUPING_DEFAULTS), per raw file (raw.py: a tree's Table 1 source frames) and pooled. The ground truth is an oracle
used for scoring only."""
import os
import sys

import torch
from census import segment

from sdn3d.evaluation.proposal_recall import match_proposals, min_pixels_at
from sdn3d.semantic.predict import GROUPING_DEFAULTS

ARMS = {"main": {**GROUPING_DEFAULTS, "thing_odds": None, "split_separation": None}, "branch": dict(GROUPING_DEFAULTS)}
pooled = {}
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); size = raw["size"]
    for arm, g in ARMS.items():
        for iou in (0.5, 0.3):
            counts = None
            for fr in raw["frames"].values():
                inst = segment(fr, raw["things"], g)[0]
                c = match_proposals(inst[None], fr["gt_instances"][None], raw["things"], min_pixels_at(*size), iou)
                counts = c if counts is None else counts + c
            s = counts.summary(); pooled[(arm, iou)] = pooled.get((arm, iou), type(counts)()) + counts
            print(f"{os.path.basename(path):16s} {arm:6s} IoU>={iou}: recall {s['recall']:.3f} ({sum(counts.found.values())}/{s['objects']}), precision {s['precision']:.3f} ({counts.true_proposals}/{s['proposals']} proposals)")
if len(sys.argv) > 2:
    for (arm, iou), counts in pooled.items():
        s = counts.summary()
        print(f"{'pooled':16s} {arm:6s} IoU>={iou}: recall {s['recall']:.3f} ({sum(counts.found.values())}/{s['objects']}), precision {s['precision']:.3f} ({counts.true_proposals}/{s['proposals']} proposals)")
