# ruff: noqa: E402, E501, E701, E702
"""CPU time of derender's geometric step with the crops read from the working image or from the photo (tuning tree
val13, 312x96, ground-truth masks, no fit; alternating, 1 thread, process_time): what reading the photo costs.

    python cost_check.py DATA GEOMETRIC.ckpt [FRAMES]
"""
import sys
import time

import numpy as np
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.sources import load_split
from sdn3d.derender import derender
from sdn3d.models import Models

torch.set_num_threads(1)
data, ckpt = sys.argv[1:3]
n = int(sys.argv[3]) if len(sys.argv) > 3 else 20
source = synth_data_source(data)
records = sorted([r for p in ("train", "val", "test") for r in load_split(source, p)], key=lambda r: r.key)
records = [records[i] for i in np.linspace(0, len(records) - 1, n).round().astype(int)]
models = Models.from_checkpoints(geometric=ckpt, crop_size=64, margin=0.1)
size = (312, 96)
times = {"image": [], "photo (incl. reading the file)": []}
for rec in records:
    frame = load_frame(rec, size, semantic=False, instances=False)
    gt = ground_truth(rec, size)
    for _ in range(2):
        t = time.process_time(); derender(frame.image, frame.intrinsics, models, "gt", gt); times["image"].append(time.process_time() - t)
        t = time.process_time(); derender(frame.image, frame.intrinsics, models, "gt", gt, photo=frame_photo(rec, size))
        times["photo (incl. reading the file)"].append(time.process_time() - t)
for k, v in times.items():
    print(f"{k}: median {1000 * np.median(v):.1f} ms CPU per frame, mean {1000 * np.mean(v):.1f} ms ({len(v)} runs)")
