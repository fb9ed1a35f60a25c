# ruff: noqa: E501, E701, E702
"""scout_second.py RAW.pt... : scouting (no code change behind it) of a rule for the split's far-group second parts.
Run from the worktree root with PYTHONPATH=src on session 21 hidden's raw.py files (tuning trees 35/37/31 at 312x96).
Main's grouping (GROUPING_DEFAULTS), then its split second parts (k - 1 in [K, 2K), K = top_k) whose votes' mean lies
outside their own bounding box (the part rule's 'centred' test, which the split's second parts skip) are either
dropped (arm 'drop': no instance's) or given back to their first part (arm 'back': the split undone). Scored with
match_proposals (Car / Van over the paper's pixel filter, one proposal per object; ground truth = oracle, scoring only):
recall and precision at IoU >= 0.5, merged proposals (hidden's rule) and proposals on no car pixel."""
import sys

import torch

from sdn3d.evaluation.proposal_recall import match_proposals, min_pixels_at
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

torch.set_num_threads(1)
K = G["top_k"]


def main_grouping(fr, things):
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=G["thing_odds"],
                          threshold=G["center_threshold"], nms_kernel=G["nms_kernel"], top_k=G["top_k"], min_area=G["min_area"],
                          split_separation=G["split_separation"], part_separation=G["part_separation"])[0][0]


def arm(inst, fr, how):
    if how == "main": return inst
    h, w = inst.shape
    vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
    pix = torch.stack([uu, vv], -1); vote = pix + fr["offset"].permute(1, 2, 0)
    out = inst.clone()
    for i in inst.unique().tolist():
        k = i % INSTANCE_DIVISOR - 1
        if not K <= k < 2 * K: continue
        P = inst == i; m = vote[P].mean(0)
        if bool(((m >= pix[P].amin(0)) & (m <= pix[P].amax(0))).all()): continue
        if how == "drop": out[P] = 0; continue
        first = [j for j in inst.unique().tolist() if j > 0 and j % INSTANCE_DIVISOR - 1 == k - K]
        out[P] = first[0] if first else i
    return out


stats = {a: {"found": 0, "objects": 0, "true": 0, "props": 0, "merged": 0, "bg": 0} for a in ("main", "drop", "back")}
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]; size = raw["size"]
    for fr in raw["frames"].values():
        base = main_grouping(fr, things); gi = fr["gt_instances"]
        car = (gi >= INSTANCE_DIVISOR) & torch.isin(gi // INSTANCE_DIVISOR, torch.tensor(things))
        cars = [gi == c for c in gi.unique().tolist() if c >= INSTANCE_DIVISOR and c // INSTANCE_DIVISOR in things and int((gi == c).sum()) >= 16]
        for a, st in stats.items():
            inst = arm(base, fr, a)
            c = match_proposals(inst[None], gi[None], things, min_pixels_at(*size), 0.5); s = c.summary()
            st["found"] += sum(c.found.values()); st["objects"] += s["objects"]; st["true"] += c.true_proposals; st["props"] += s["proposals"]
            for i in inst.unique().tolist():
                if i <= 0: continue
                P = inst == i; st["bg"] += int(not (P & car).any())
                st["merged"] += sum(int((P & m).sum()) >= max(16, 0.3 * int(m.sum())) for m in cars) >= 2
for a, st in stats.items():
    print(f"{a:5s} recall {st['found'] / st['objects']:.3f} ({st['found']}/{st['objects']}), precision {st['true'] / st['props']:.3f} "
          f"({st['true']}/{st['props']}), merged {st['merged']}, on no car {st['bg']}")
