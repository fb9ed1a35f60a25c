# ruff: noqa: E402, E501, E701, E702  (a one-off record script, kept as it ran)
"""Capture the fit_to_masks inputs of pose_table's fit row (GT masks + boxes: oracle) on a tree, with the truth.

python capture.py DATA OUT.pt [--max-frames 0]
"""

import sys
import time

import torch

sys.path.insert(0, "benchmarks")
torch.set_num_threads(1)
torch.manual_seed(0)
import pose_table as pt

import sdn3d.geometric.fit as fit_module
from sdn3d.derender import BoxPrompts, derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.models import Models, geometric_crop_settings

data, out = sys.argv[1], sys.argv[2]
geo = "/tmp/h5runs/big_mb40/checkpoints/last.ckpt"
crop = geometric_crop_settings(geo)
models = Models.from_checkpoints(geometric=geo, **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
source = pt.synth_data_source(data)
records = sorted([r for part in ("train", "val", "test") for r in pt.load_split(source, part)], key=lambda r: r.key)
size = tuple(source.image_size)
captured = []
real = fit_module.fit_to_masks


def fake(masks, boxes, intr, **kw):
    captured.append(
        {
            "masks": masks.clone(),
            "boxes": boxes.clone(),
            "intr": intr,
            **{
                k: (v.clone() if isinstance(v, torch.Tensor) else v)
                for k, v in kw.items()
                if k not in ("settings", "yaw_belief")
            },
            "yaw_belief": kw.get("yaw_belief"),
        }
    )
    assert kw.get("yaw_belief") is None
    return real(masks, boxes, intr, **{**kw, "settings": FitSettings(coarse_steps=0, fine_steps=0, keep=1)})


fit_module.fit_to_masks = fake
frames = []
t0 = time.time()
for record in records:
    frame = pt.load_frame(record, size, semantic=False, instances=False)
    gt = pt.ground_truth(record, size)
    truth = pt.scene_from_frame(record, size)
    ids, boxes = [], []
    for iid in truth.objects.instance_id.tolist():
        k, cls = iid % INSTANCE_DIVISOR, iid // INSTANCE_DIVISOR
        r = pt.row_of(truth, iid)
        if (
            cls not in (12, 13)
            or k not in gt.boxes
            or int(truth.objects.mask[r].sum()) < 256
            or truth.objects.template_id[r] < 0
        ):
            continue
        ids.append(iid)
        left, top, right, bottom = gt.boxes[k].tolist()
        boxes.append([left, top, right + 1, bottom + 1])
    if not ids:
        continue
    names = tuple("Car" if i // INSTANCE_DIVISOR == 12 else "Van" for i in ids)
    gt_masks = torch.stack([truth.objects.mask[pt.row_of(truth, i)] for i in ids])
    n0 = len(captured)
    derender(
        frame.image,
        frame.intrinsics,
        models,
        "boxes",
        gt,
        boxes=BoxPrompts(torch.tensor(boxes), names, FitSettings(), masks=gt_masks, refine_masks=False),
    )
    assert len(captured) == n0 + 1 and captured[-1]["masks"].shape[0] == len(ids)
    t = truth.objects
    rows = [pt.row_of(truth, i) for i in ids]
    frames.append(
        {
            "key": record.key,
            "ids": ids,
            "args": captured[-1],
            "true_ry": t.ry[rows].float(),
            "true_template": t.template_id[rows],
            "true_center": t.center[rows].float(),
            "true_dims": t.dims[rows].float(),
            "true_mask": t.mask[rows],
            "others": torch.stack([t.mask.any(0) & ~t.mask[r] for r in rows]),
        }
    )
    print(record.key, len(ids), round(time.time() - t0), file=sys.stderr)
torch.save(frames, out)
print("frames", len(frames), "objects", sum(len(f["ids"]) for f in frames))
