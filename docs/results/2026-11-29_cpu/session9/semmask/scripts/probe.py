# ruff: noqa: E402, E501, E701, E702
"""probe.py TREE COUNT.json: the semantic branch's vehicle probability (Car+Van+Truck) in the rows below each
fitted semantic proposal's bottom (within its columns), for proposals missing the car's bottom and for the others."""
import json
import sys

import torch

from sdn3d.data.frames import load_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.models import Models

torch.set_num_threads(1)
tree, cnt = sys.argv[1:3]
S = "/tmp/s5data/lead/demo/runs/semantic/checkpoints/inference.pt"
models = Models.from_checkpoints(S, None, None)
records = index_records(read_frames(tree)); rows = json.load(open(cnt))
segs = {}
for x in rows:
    w, var, fr = x["key"].split()[0].split("/") + [x["key"].split()[1]]
    k = (w, var, int(fr))
    if k not in segs:
        f = load_frame(records[k], (312, 96), semantic=False, instances=False)
        segs[k] = models.semantic(f.image)
    seg = segs[k]
    m = seg.instance[0] == x["id"]
    p = seg.probability[0, 11:14].sum(0)
    cols = m.any(0).nonzero().flatten()
    b = x["bottom"]; h = x["gt_bottom"] - x["gt_top"] + 1
    miss = x["gt_bottom"] - x["bottom"] >= max(2, 0.15 * h)
    below = [float(p[b + d, cols].mean()) if b + d < 96 else float("nan") for d in (1, 2, 3, 4, 5)]
    lab = [int((seg.label[0, b + d, cols] >= 11).sum()) if b + d < 96 else -1 for d in (1, 2, 3)]
    print(("MISS " if miss else "ok   ") + f"{x['key']:18s} {x['id']} rows {x['top']}-{b} gt {x['gt_top']}-{x['gt_bottom']} width {len(cols)} p_vehicle below +1..+5: " + " ".join(f"{v:.2f}" for v in below) + f" zerr {x['z_err']:+.2f} veh-labelled-below {lab}")
