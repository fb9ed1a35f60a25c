"""cost.py TREE OUT.json: the CPU time (time.process_time, one torch thread) of derender on predicted proposals with
the proposals' fit (semantic branch, photo crops, 312x96, w0) on the pose table's 40 frames of TREE, per frame, for
the code on the path (PYTHONPATH=CODE/src). Run once per code, both at once on the shared machine; compare per frame
(paired)."""
import json
import sys
import time

import numpy as np
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.sources import load_split
from sdn3d.derender import derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models, geometric_crop_settings

RUNS = "/tmp/s21data/demo/out/runs"
SIZE = (312, 96)
torch.set_num_threads(1)
geo = f"{RUNS}/geometric/checkpoints/best-epoch009.ckpt"
crop = geometric_crop_settings(geo)
models = Models.from_checkpoints(geometric=geo, semantic=f"{RUNS}/semantic/checkpoints/best-epoch013.ckpt",
                                 **({"crop_size": crop[0], "margin": crop[1]} if crop else {}))
source = synth_data_source(sys.argv[1])
records = sorted((r for p in ("train", "val", "test") for r in load_split(source, p)), key=lambda r: r.key)
records = [records[i] for i in np.linspace(0, len(records) - 1, 40).round().astype(int)]
out = {}
for r in records:
    f = load_frame(r, SIZE, semantic=False, instances=False)
    photo, gt = frame_photo(r, SIZE), ground_truth(r, SIZE)
    t0 = time.process_time()
    derender(f.image, f.intrinsics, models, "semantic", gt, fit=FitSettings(), photo=photo)
    out[r.key] = time.process_time() - t0
json.dump(out, open(sys.argv[2], "w"))
print(f"{len(out)} frames, CPU {sum(out.values()):.1f} s")
