# ruff: noqa: E402, E501, E701, E702, I001
"""Diagnosis (tuning tree val13): the red-lamp reading of each evaluated car under crop variants, to see why the
photo's crops alone do not fix the flips. Variants: working-size crop + working mask (today's), photo crop +
working mask (nearest), photo crop + the frame's own-resolution ground-truth mask (oracle), 624x192 working size.

    python lamp_diag.py DATA OUT.json
"""
import json
import sys

import torch

from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
from sdn3d.cli._config import synth_data_source
from sdn3d.editing.frame import PixelFrame
from sdn3d.geometric.lamps import LampCue, red_lamps
from sdn3d.image_ops import crop_windows, square_crop_window
from sdn3d.labels import INSTANCE_DIVISOR
import numpy as np

data, out = sys.argv[1:3]
source = synth_data_source(data)
records = sorted([r for p in ("train", "val", "test") for r in load_split(source, p)], key=lambda r: r.key)
records = [records[i] for i in np.linspace(0, len(records) - 1, 40).round().astype(int)]
cue = LampCue()
from sdn3d.models import Models
models = Models.from_checkpoints(geometric=sys.argv[3], crop_size=64, margin=0.1)
rows = []
for rec in records:
    res = {}
    for size in ((312, 96), (624, 192)):
        gt = ground_truth(rec, size); truth = scene_from_frame(rec, size)
        res[size] = (gt, truth, load_frame(rec, size, semantic=False, instances=False).image)
    own = load_frame(rec, None, semantic=False, instances=False).image
    photo = PixelFrame((own.shape[-1], own.shape[-2]), (312, 96)).photo(own)
    gt, truth, image = res[(312, 96)]
    gt6, truth6, image6 = res[(624, 192)]
    for r, iid in enumerate(truth.objects.instance_id.tolist()):
        k, cls = iid % INSTANCE_DIVISOR, iid // INSTANCE_DIVISOR
        if cls not in (12, 13) or k not in gt.boxes or int(truth.objects.mask[r].sum()) < 64 or truth.objects.template_id[r] < 0:
            continue
        r6 = (truth6.objects.instance_id == iid).nonzero().flatten()[0]
        w = torch.tensor([square_crop_window(gt.boxes[k], 0.1)], dtype=torch.float32)
        w6 = torch.tensor([square_crop_window(gt6.boxes[k], 0.1)], dtype=torch.float32)
        m = crop_windows(truth.objects.mask[r][None, None].float(), w, 64, "nearest")
        m_own = crop_windows(truth6.objects.mask[r6][None, None].float(), photo.windows(w), 64, "nearest")
        m6 = crop_windows(truth6.objects.mask[r6][None, None].float(), w6, 64, "nearest")
        m_smooth = (crop_windows(truth.objects.mask[r][None, None].float(), w, 64, "bilinear") > 0.5).float()
        variants = {"image": (crop_windows(image, w, 64, "bilinear"), m), "photo": (photo.crops(w, 64), m),
                    "photo_smooth": (photo.crops(w, 64), m_smooth), "image_smooth": (crop_windows(image, w, 64, "bilinear"), m_smooth),
                    "photo_ownmask": (photo.crops(w, 64), m_own), "at624": (crop_windows(image6, w6, 64, "bilinear"), m6)}
        row = {"frame": rec.key, "id": iid, "pixels": int(truth.objects.mask[r].sum()), "true_ry": float(truth.objects.ry[r])}
        for name, (c, mm) in variants.items():
            p, u, o = red_lamps(c * mm, mm, cue)
            red = ((c[:, 0] > cue.red_min) & (c[:, 0] > cue.ratio * c[:, 1]) & (c[:, 0] > cue.ratio * c[:, 2]))
            box = gt.boxes[k][None].float() if name != "at624" else gt6.boxes[k][None].float()
            intr = res[(312, 96) if name != "at624" else (624, 192)][1].intrinsics
            iv = torch.tensor([[intr.fx, intr.fy, intr.cx, intr.cy]], dtype=torch.float32)
            pred = models.geometric.predict(c * mm, mm, box, iv)
            d = float(pred["ry"][0]) - row["true_ry"]
            import math
            yaw = abs(math.degrees(math.atan2(math.sin(d), math.cos(d))))
            row[name] = {"yaw": yaw, "present": bool(p), "usable": bool(u), "mask": int((mm > 0.5).sum()),
                         "red_in": int((red & (mm[:, 0] > 0.5)).sum()), "red_all": int(red.sum())}
        rows.append(row)
json.dump(rows, open(out, "w"))
print(len(rows))
