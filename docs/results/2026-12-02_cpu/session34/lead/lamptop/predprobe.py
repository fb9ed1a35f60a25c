# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""predprobe.py W EXAMPLES.json: for each (tree, frame, id), de-render the frame from the semantic branch's proposals
with the fit (as pose_table's pred_fit) and print what the geometric branch read of the proposal matched to the car."""
import sys, json, math, torch
sys.path.insert(0, "/work/main/benchmarks")
import sdn3d.derender as D
from sdn3d.derender import derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models
from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
from sdn3d.image_ops import mask_boxes, pixel_centre_boxes
import pose_table

W, ex = sys.argv[1], json.load(open(sys.argv[2]))
models = Models.from_checkpoints(geometric=f"{W}/geometric/checkpoints/inference.pt", semantic=f"{W}/semantic/checkpoints/inference.pt")
calls = []
orig = D._predict_geometry
def wrapped(image, intr, masks, boxes, *a, **k):
    r = orig(image, intr, masks, boxes, *a, **k)
    calls.append((boxes.clone(), {kk: v.detach().cpu().clone() for kk, v in r.items() if torch.is_tensor(v)}))
    return r
D._predict_geometry = wrapped
size = (312, 96)
import os
if os.environ.get("NOBAND"):
    import torch as _t
    D.unsure_below = lambda masks, fraction=None: _t.zeros_like(masks, dtype=_t.bool)
for tree, key, iid in ex:
    source = synth_data_source(tree)
    rec = [r for part in ("train", "val", "test") for r in load_split(source, part) if r.key == key][0]
    frame = load_frame(rec, size, semantic=False, instances=False)
    gt = ground_truth(rec, size); truth = scene_from_frame(rec, size)
    calls.clear()
    scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, fit=FitSettings())
    tmask = truth.objects.mask[pose_table.row_of(truth, iid)].bool()
    o = scene.objects
    ious = [(float((o.mask[r].bool() & tmask).sum()) / max(1, float((o.mask[r].bool() | tmask).sum())), r) for r in range(len(o.mask))]
    iou, r = max(ious)
    box = pixel_centre_boxes(mask_boxes(o.mask[r:r + 1].bool()))[0]
    tr = pose_table.row_of(truth, iid)
    line = f"{key} {iid} iou {iou:.2f} true_ry {float(truth.objects.ry[tr]):+.2f} fit_ry {float(o.ry[r]):+.2f} | "
    for n, (bx, res) in enumerate(calls):
        d = (bx - box).abs().amax(1)
        j = int(d.argmin())
        if float(d[j]) > 1.5: continue
        line += f"call{n}: lamp p/u/off {int(res['lamp_present'][j])}{int(res['lamp_usable'][j])}/{float(res['lamp_offset'][j]):+.2f} front {int(res['front_present'][j]) if 'front_present' in res else '-'}{int(res['front_usable'][j]) if 'front_usable' in res else '-'} net_ry {float(res['net_ry'][j]):+.2f} ry {float(res['ry'][j]):+.2f} ray {float(res['ray'][j]):+.2f} border {float(res['border_side'][j]) if 'border_side' in res else 0:+.0f}; "
    print(line, flush=True)
