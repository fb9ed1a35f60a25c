# ruff: noqa: E402, E501, E701, E702
"""gap.py TREE CACHE: for semantic proposals missing the car's bottom, what the gap pixels (ground-truth mask minus proposal) are in the scene: semantic label, other instance."""
import collections
import os
import sys

import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records

tree, cache = sys.argv[1:3]
records = index_records(read_frames(tree))
tot = collections.Counter()
for line in open(os.path.join(cache, "keys.txt")):
    k, f = line.rsplit(" ", 1); w, var, fr = k.split("_")[:3]
    if "semantic" not in k.lower(): continue
    scene = torch.load(os.path.join(cache, f.strip()), weights_only=False)
    gt = scene_from_frame(records[(w, var, int(fr))], (312, 96)); gm = gt.objects.mask
    fits = {x["id"]: x for x in scene.meta.get("fits", [])}
    names = {}
    for i, iid in enumerate(scene.objects.instance_id.tolist()):
        if iid not in fits or fits[iid]["fit_iou"] is None: continue
        m = scene.objects.mask[i]
        iou = (gm & m).flatten(1).sum(1).float() / (gm | m).flatten(1).sum(1).float().clamp_min(1); g = int(iou.argmax())
        if iou[g] < 0.2: continue
        ys = m.any(1).nonzero().flatten(); gys = gm[g].any(1).nonzero().flatten()
        if gys.max() - ys.max() < max(2, 0.15 * (gys.max() - gys.min() + 1)): continue
        gap = gm[g] & ~m
        owner = (scene.objects.mask[:, gap].long() * torch.arange(1, len(scene.objects.mask) + 1)[:, None]).sum(0)
        sem = scene.semantic[gap]
        c = collections.Counter(("other inst" if o > 0 else f"sem {int(s)}") for o, s in zip(owner.tolist(), sem.tolist(), strict=True))
        tot.update(c)
        print(k[:20], iid, "rows", int(ys.min()), int(ys.max()), "gt", int(gys.min()), int(gys.max()), "gap px", int(gap.sum()), dict(c), "fitiou", fits[iid]["fit_iou"])
print("gap pixels in all:", dict(tot))
