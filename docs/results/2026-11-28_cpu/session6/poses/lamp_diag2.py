# ruff: noqa: E402, E501, E701, E702
"""Diagnosis 2 (tuning tree val13 only): the net's yaw from the crop the branch is given, then the lamp cue read
with another mask: the working mask as sampled (nearest), or only the crop pixels surely inside it (the working
mask's bilinear sample >= a threshold: half a working pixel in from its edge), for the lamp pixels only or for
everything the cue reads. Flips (> 90 deg) per variant on the 146 cars and vans of pose_table's gt rows.

    python lamp_diag2.py DATA GEOMETRIC.ckpt
"""
import math
import sys

import numpy as np
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
from sdn3d.editing.frame import PixelFrame
from sdn3d.geometric.lamps import LampCue, face_by_lamps
from sdn3d.geometric.model import ray_angle
from sdn3d.image_ops import crop_windows, square_crop_window
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.models import Models

data, ckpt = sys.argv[1:3]
size = (int(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) > 4 else (312, 96)
minpx = 64 if size[0] == 312 else 64
source = synth_data_source(data)
records = sorted([r for p in ("train", "val", "test") for r in load_split(source, p)], key=lambda r: r.key)
records = [records[i] for i in np.linspace(0, len(records) - 1, 40).round().astype(int)]
cue = LampCue()
models = Models.from_checkpoints(geometric=ckpt, crop_size=64, margin=0.1)
models.geometric.lamp_cue = None
flips: dict[str, list] = {}
for rec in records:
    gt, truth = ground_truth(rec, size), scene_from_frame(rec, size)
    image = load_frame(rec, size, semantic=False, instances=False).image
    own = load_frame(rec, None, semantic=False, instances=False).image
    photo = PixelFrame((own.shape[-1], own.shape[-2]), size).photo(own)
    intr = truth.intrinsics
    for r, iid in enumerate(truth.objects.instance_id.tolist()):
        k, cls = iid % INSTANCE_DIVISOR, iid // INSTANCE_DIVISOR
        if cls not in (12, 13) or k not in gt.boxes or int(truth.objects.mask[r].sum()) < minpx or truth.objects.template_id[r] < 0:
            continue
        w = torch.tensor([square_crop_window(gt.boxes[k], 0.1)], dtype=torch.float32)
        mk = truth.objects.mask[r][None, None].float()
        m = crop_windows(mk, w, 64, "nearest")
        soft = crop_windows(mk, w, 64, "bilinear")
        box = gt.boxes[k][None].float()
        iv = torch.tensor([[intr.fx, intr.fy, intr.cx, intr.cy]], dtype=torch.float32)
        ray = ray_angle(box, iv)
        true_ry = float(truth.objects.ry[r])
        for src, crop in (("image", crop_windows(image, w, 64, "bilinear")), ("photo", photo.crops(w, 64))):
            net_ry = models.geometric.predict(crop * m, m, box, iv)["ry"]
            for mname, lm in (("nearest", m), ("sure0.999", (soft > 0.999).float()), ("sure0.99", (soft > 0.99).float()), ("sure0.9", (soft > 0.9).float()), ("sure0.75", (soft > 0.75).float()),
                              ("soft0.5", (soft > 0.5).float())):
                ry = face_by_lamps(net_ry, ray, crop * lm, lm, cue)
                d = float(ry[0]) - true_ry
                flips.setdefault(f"{src}/{mname}", []).append(abs(math.degrees(math.atan2(math.sin(d), math.cos(d)))) > 90)
for key, v in flips.items():
    print(f"{key}: {sum(v)} of {len(v)} flips ({100 * np.mean(v):.1f} %)")
