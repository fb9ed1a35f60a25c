"""jtime.py NAME REPEATS: CPU seconds (time.process_time, one torch thread) of the de-render of each joined tuning frame
(predicted proposals, FitSettings(), w28, 312x96, with the photo: as derun.py), the code on PYTHONPATH, REPEATS timed
calls per frame after one warm-up call; one JSON line per frame (session 29 joincost29; run by jtime.sh, which
alternates main's tree and the branch's). NAME ``nojoin``: the same de-render without the join
(``FitSettings(join_overlap=None)``: the first pass alone, what the frame would cost without one)."""
import json
import sys
import time

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth
from sdn3d.data.sources import read_source
from sdn3d.derender import derender
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.models import Models

torch.set_num_threads(1)
R = "/tmp/s28/demo2/outputs/demo/runs"
FRAMES = [(11, "vkitti1/0001/clone/00034"), (11, "vkitti1/0001/rain/00034"), (37, "vkitti1/0001/rain/00037")]
models = Models.from_checkpoints(semantic=f"{R}/semantic/checkpoints/inference.pt",
                                 geometric=f"{R}/geometric/checkpoints/inference.pt")
name, repeats = sys.argv[1], int(sys.argv[2])
for seed, key in FRAMES:
    tree = f"/tmp/s28/merge40/trees/t1_{seed}"
    rec = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}[key]
    frame = load_frame(rec, (312, 96), semantic=False, instances=False)
    gt, photo = ground_truth(rec, (312, 96)), frame_photo(rec, (312, 96))
    times = []
    for k in range(repeats + 1):
        t = time.process_time()
        derender(frame.image, frame.intrinsics, models, "semantic", gt, photo=photo,
                 fit=FitSettings(join_overlap=None) if name == "nojoin" else FitSettings())
        if k:
            times.append(round(time.process_time() - t, 4))
    print(json.dumps({"code": name, "seed": seed, "key": key, "cpu_s": times}), flush=True)
