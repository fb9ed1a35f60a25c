# ruff: noqa: E501, E701, E702, E401, B905
"""vdist.py RAW.pt... (session 21 hidden, run from the worktree root with PYTHONPATH=src:. on main's grouping, before the stray rule existed):
per merged proposal, its pixels' vote distance from its median vote over the median of those distances, quantiles of the
occluder's and the hidden car's pixels (oracle), and the share of single-car proposals' car pixels over 3-6x."""
import sys

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as g

for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]
    allO = []; allH = []; single = []
    for key, fr in raw["frames"].items():
        prob = fr["logits"].float().softmax(0)[None]
        inst = group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"], nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"], part_separation=g["part_separation"])[0][0]
        gi = fr["gt_instances"]; h, w = gi.shape
        vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
        vote = torch.stack([uu + fr["offset"][0], vv + fr["offset"][1]], -1)
        cars = {int(i): gi == i for i in gi.unique().tolist() if i >= 1000 and i // 1000 in things and int((gi == i).sum()) >= 16}
        for p in inst.unique().tolist():
            if p <= 0: continue
            P = inst == p; vp = vote[P]; med = vp.median(0).values; d = (vp - med).norm(dim=-1); s = d.median().clamp_min(0.5)
            held = [c for c, m in cars.items() if int((P & m).sum()) >= max(16, 0.3 * int(m.sum()))]
            held.sort(key=lambda c: fr["gt_range"].get(c % 1000, 1e9))
            nd = ((vote - med).norm(dim=-1) / s)
            if len(held) >= 2:
                O = cars[held[0]] & P; Hm = cars[held[1]] & P
                print(f"{key:28s} P{p} O{held[0]} H{held[1]} sd {float(s):.1f}px  O q50/q90/q99 {nd[O].quantile(.5):.1f}/{nd[O].quantile(.9):.1f}/{nd[O].quantile(.99):.1f}  H q10/q50/q90 {nd[Hm].quantile(.1):.1f}/{nd[Hm].quantile(.5):.1f}/{nd[Hm].quantile(.9):.1f}")
            elif len(held) == 1:
                C = cars[held[0]] & P; single.append(nd[C])
    s = torch.cat(single)
    print("single-car proposals' car pixels: share over 3/4/5/6 x median:", [round(float((s > k).float().mean()), 3) for k in (3, 4, 5, 6)])
