# ruff: noqa: E501, E701, E702, B905
"""recall.py RAW.pt... (session 20 comp's, with stray_distance, merged proposals and mean best IoU added): proposal recall at IoU >= 0.5 and >= 0.3 and precision (IoU >= 0.5) of grouping variants on the
frames session 19 inst's raw.py saved (a Table 1 tree's source frames at 312x96, the demo's weights), per file and
pooled (sdn3d.evaluation.proposal_recall.match_proposals: annotated Car/Van objects over the paper's pixel filter at
the size, one proposal per object; the ground truth is an oracle used for scoring only). Every arm groups through
sdn3d.semantic.panoptic.group_vehicles, the predictor's entry point, with GROUPING_DEFAULTS and the arm's overrides.
ARMS='{"name": {overrides}, ...}' (default: main = stray_distance None, and the installed defaults; an arm of null is
the floor of benchmarks/proposal_recall.py: one proposal per 8-connected component of the arg-max's Car / Van pixels);
also prints each arm's proposals that hold pixels of no annotated car at all ("on background"), its merged
proposals (holding >= 30 % and >= 16 px of each of two or more Car / Van of >= 16 px, merged.py's rule) and the mean
over the cars over the pixel filter of their best proposal IoU."""
import json
import os
import sys

import torch

from benchmarks.proposal_recall import components
from sdn3d.evaluation.proposal_recall import match_proposals, min_pixels_at
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

ARMS = json.loads(os.environ.get("ARMS", '{"main": {"stray_distance": null}, "defaults": {}}'))


def group(fr, things, g):
    if g is None:
        return components(fr["logits"].float().argmax(0), things)[None]
    prob = fr["logits"].float().softmax(0)[None]
    inst, _ = group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"],
                             threshold=g["center_threshold"], nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"],
                             split_separation=g["split_separation"], part_separation=g.get("part_separation"),
                             stray_distance=g.get("stray_distance"), stray_reach=g.get("stray_reach", 0.0))
    return inst


raws = [torch.load(p, weights_only=False) for p in sys.argv[1:]]
for arm, over in ARMS.items():
    g = None if over is None else {**GROUPING_DEFAULTS, **over}
    pooled = {}; bg = 0; nprop = 0; nfr = 0; merged = 0; ious = []
    for path, raw in zip(sys.argv[1:], raws):
        things, size = raw["things"], raw["size"]
        insts = {k: group(fr, things, g) for k, fr in raw["frames"].items()}
        for iou in (0.5, 0.3):
            counts = None
            for k, fr in raw["frames"].items():
                c = match_proposals(insts[k], fr["gt_instances"][None], things, min_pixels_at(*size), iou)
                counts = c if counts is None else counts + c
            pooled[iou] = counts if iou not in pooled else pooled[iou] + counts
            s = counts.summary()
            print(f"{os.path.basename(path):14s} {arm:12s} IoU>={iou}: recall {s['recall']:.3f} ({sum(counts.found.values())}/{s['objects']}), precision {s['precision']:.3f} ({counts.true_proposals}/{s['proposals']})")
        for k, fr in raw["frames"].items():
            gi = fr["gt_instances"]; car = (gi >= INSTANCE_DIVISOR) & torch.isin(gi // INSTANCE_DIVISOR, torch.tensor(things))
            ids = insts[k][0].unique(); ids = ids[ids > 0]
            nprop += ids.numel(); nfr += 1; bg += sum(int(not (car & (insts[k][0] == i)).any()) for i in ids)
            cars = [gi == c for c in gi.unique().tolist() if c >= INSTANCE_DIVISOR and c // INSTANCE_DIVISOR in things and int((gi == c).sum()) >= 16]
            for i in ids.tolist():
                P = insts[k][0] == i; merged += sum(int((P & m).sum()) >= max(16, 0.3 * int(m.sum())) for m in cars) >= 2
            for m in cars:
                if int(m.sum()) > min_pixels_at(*size):
                    ious.append(max([int(((insts[k][0] == i) & m).sum()) / int(((insts[k][0] == i) | m).sum()) for i in ids.tolist()] or [0.0]))
    if len(raws) > 1:
        for iou, counts in pooled.items():
            s = counts.summary()
            print(f"{'pooled':14s} {arm:12s} IoU>={iou}: recall {s['recall']:.3f} ({sum(counts.found.values())}/{s['objects']}), precision {s['precision']:.3f} ({counts.true_proposals}/{s['proposals']})")
    print(f"{'pooled':14s} {arm:12s} proposals {nprop} over {nfr} frames, {bg} on background (no annotated car pixel), {merged} merged; mean best IoU {sum(ious) / len(ious):.4f} over {len(ious)} cars")
