# ruff: noqa: E501, E701, E702, E401, B905
"""reach.py RAW.pt... (session 21 hidden, run from the worktree root with PYTHONPATH=src:. on main's grouping, before the stray rule existed):
per pixel of main's proposals, the reach |vote - m| / max(|pixel - m|, 3) (m: the proposal's median vote), for single-car
proposals' car pixels, merged proposals' occluder and hidden-car pixels, and background pixels in proposals (oracle)."""
import sys

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as g

for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]; single = []; Os = []; Hs = []; bg = []
    for _key, fr in raw["frames"].items():
        prob = fr["logits"].float().softmax(0)[None]
        inst = group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"], nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"], part_separation=g["part_separation"])[0][0]
        gi = fr["gt_instances"]; h, w = gi.shape
        vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
        pix = torch.stack([uu, vv], -1); vote = pix + fr["offset"].permute(1, 2, 0)
        cars = {int(i): gi == i for i in gi.unique().tolist() if i >= 1000 and i // 1000 in things and int((gi == i).sum()) >= 16}
        for p in inst.unique().tolist():
            if p <= 0: continue
            P = inst == p; med = vote[P].median(0).values
            r = (vote - med).norm(dim=-1) / (pix - med).norm(dim=-1).clamp_min(3)
            held = sorted([c for c, m in cars.items() if int((P & m).sum()) >= max(16, 0.3 * int(m.sum()))], key=lambda c: fr["gt_range"].get(c % 1000, 1e9))
            carpx = torch.zeros_like(P)
            for m in cars.values(): carpx |= m
            bg.append(r[P & ~carpx])
            if len(held) >= 2: Os.append(r[P & cars[held[0]]]); Hs.append(r[P & cars[held[1]]])
            elif len(held) == 1: single.append(r[P & cars[held[0]]])
    for name, xs in (("single-car", single), ("occluder", Os), ("hidden", Hs), ("background in proposals", bg)):
        x = torch.cat(xs); print(f"{path[-12:]} {name:24s} n={x.numel():6d} q10/50/90 {x.quantile(.1):.2f}/{x.quantile(.5):.2f}/{x.quantile(.9):.2f}  >0.3 {float((x>0.3).float().mean()):.3f} >0.5 {float((x>0.5).float().mean()):.3f} >0.7 {float((x>0.7).float().mean()):.3f}")
