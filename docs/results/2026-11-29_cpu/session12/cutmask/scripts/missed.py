# ruff: noqa: E501
"""missed.py TREE CAPTURE_DIR: over every captured fitted semantic proposal (capture.py) matched to a ground-truth car
(largest mask IoU >= 0.2, oracle, for measurement only) whose mask stops >= 2 px above the car's visible bottom, what the
semantic branch says the car's missed pixels are (its class map; other proposals' pixels counted apart), per weather."""
import collections
import glob
import sys

import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.labels import VKITTI_CLASS_INDEX

inv = {v: k for k, v in VKITTI_CLASS_INDEX.items()}
records = index_records(read_frames(sys.argv[1]))
count = collections.defaultdict(collections.Counter)
for f in sorted(glob.glob(sys.argv[2] + "/*.pt")):
    c = torch.load(f, weights_only=False)
    _, w, var, fr = c["source"].split("/")
    gm = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects.mask
    taken = c["masks"].any(0)
    for r in c["rows"].tolist():
        m = c["masks"][r]
        iou = (gm & m).flatten(1).sum(1).float() / (gm | m).flatten(1).sum(1).float().clamp_min(1)
        g = int(iou.argmax())
        if iou[g] < 0.2 or int(gm[g].any(1).nonzero().max() - m.any(1).nonzero().max()) < 2:
            continue
        miss = gm[g] & ~m
        count[var]["another proposal"] += int((miss & taken).sum())
        for k, v in zip(*c["semantic"][miss & ~taken].unique(return_counts=True), strict=True):
            count[var][inv.get(int(k), str(int(k)))] += int(v)
for var, cnt in sorted(count.items()):
    total = sum(cnt.values())
    print(f"{var}: {total} missed car pixels: " + ", ".join(f"{k} {100 * v / total:.0f} %" for k, v in cnt.most_common(6)))
