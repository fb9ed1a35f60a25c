"""joined_cost.py TREE KEY... : CPU seconds of one de-render (predicted proposals, the proposals' fit, w0, 312x96, one
thread) of each named source frame, the code on PYTHONPATH, 3 repeats after one warm-up (session 27 join40: a frame
with a join pays for its objects' second pass). Prints one JSON line per frame.
Run: PYTHONPATH=<code>/src OMP_NUM_THREADS=1 python joined_cost.py /tmp/s21data/trees/t1_37 vkitti1/0001/clone/00036
"""
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
R = "/tmp/s21data/demo/out/runs"
models = Models.from_checkpoints(semantic=f"{R}/semantic/checkpoints/inference.pt",
                                 geometric=f"{R}/geometric/checkpoints/inference.pt")
tree = sys.argv[1]
records = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}
for key in sys.argv[2:]:
    rec = records[key]
    frame = load_frame(rec, (312, 96), semantic=False, instances=False)
    gt, photo = ground_truth(rec, (312, 96)), frame_photo(rec, (312, 96))
    times = []
    for k in range(4):
        t = time.process_time()
        scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, fit=FitSettings(), photo=photo)
        if k:
            times.append(round(time.process_time() - t, 3))
    joined = [f["joined_from"] for f in scene.meta["fits"] if f.get("joined_from")]
    print(json.dumps({"key": key, "cpu_s": times, "objects": len(scene.objects.instance_id), "joined": joined}))
