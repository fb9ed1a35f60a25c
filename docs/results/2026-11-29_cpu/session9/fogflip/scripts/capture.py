# ruff: noqa: E402, E501, E701, E702
"""capture.py TREE OUT.pt [PROPOSALS] [ALL]: de-render every source frame of the tree's rotate entries (ALL: every
entry's) with the session-5 demo's weights at 312x96 and record, per vehicle matched to the ground truth, what the
geometric branch's lamp cue read (crop * lamp mask, lamp mask), its facing outputs, and the true yaw (oracle)."""
import os
import sys

import torch

import sdn3d.geometric.predict as P
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import Models, derender
from sdn3d.evaluation.edit_benchmark import edit_kind, index_records
from sdn3d.image_ops import mask_boxes

torch.set_num_threads(1)
tree, out = sys.argv[1], sys.argv[2]
prop = sys.argv[3] if len(sys.argv) > 3 else "gt"
every = len(sys.argv) > 4
R = "/tmp/s5data/lead/demo/runs"
models = Models.from_checkpoints(f"{R}/semantic/checkpoints/inference.pt", f"{R}/geometric/checkpoints/inference.pt", f"{R}/textural/checkpoints/inference.pt")
size = (312, 96)
entries = load_edit_benchmark(os.path.join(tree, "vkitti_edit_benchmark.json"))
recs = index_records(read_frames(tree))
frames = sorted({(e.world, e.variation, e.source_frame) for e in entries if every or edit_kind(e) == "rotate"})
if not entries:  # a pose tree (val13): its first 40 frames per world and variation
    frames = [k for k in sorted(recs) if sum(1 for j in sorted(recs) if j[:2] == k[:2] and j[2] < k[2]) < 40]
CALL = {}
orig = P.GeometricPredictor.predict
def predict(self, crop, mask, box, intrinsics, *a, lamp_mask=None, **k):
    o = orig(self, crop, mask, box, intrinsics, *a, lamp_mask=lamp_mask, **k)
    lm = mask if lamp_mask is None else lamp_mask
    CALL.update(seen=(crop * lm).half(), lamps=(lm > 0.5), box=box.clone(), out={kk: v.detach().cpu() for kk, v in o.items() if kk in ("net_ry", "ray", "yaw_bins", "yaw_residual", "yaw_ray", "ry", "lamp_present", "lamp_usable")})
    return o
P.GeometricPredictor.predict = predict


def area(b):
    return (b[:, 2] - b[:, 0]) * (b[:, 3] - b[:, 1])


rows = []
for key in frames:
    rec = recs[key]
    src = load_frame(rec, size, semantic=False, instances=False)
    CALL.clear()
    derender(src.image, src.intrinsics, models, prop, ground_truth(rec, size), min_pixels=64, photo=frame_photo(rec, size))
    if not CALL: continue
    oracle = scene_from_frame(rec, size).objects
    geo = oracle.template_id >= 0
    ob = mask_boxes(oracle.mask[geo]); ory = oracle.ry[geo]; opx = oracle.mask[geo].flatten(1).sum(1)
    pb = CALL["box"].cpu().float()
    lt = torch.maximum(pb[:, None, :2], ob[None, :, :2].float()); rb = torch.minimum(pb[:, None, 2:], ob[None, :, 2:].float())
    inter = (rb - lt).clamp_min(0).prod(-1)
    iou = inter / (area(pb)[:, None] + area(ob.float())[None] - inter)
    best, j = iou.max(1)
    for i in range(pb.shape[0]):
        if best[i] < 0.5: continue
        rows.append({"key": key, "seen": CALL["seen"][i].cpu(), "lamps": CALL["lamps"][i].cpu(), "true_ry": float(ory[j[i]]), "px": int(opx[j[i]]),
                     **{kk: v[i] for kk, v in CALL["out"].items()}})
    print(key, len(rows), flush=True)
torch.save(rows, out)
