"""derun.py OUT TREE... : main's or the branch's (PYTHONPATH) de-render of every source frame of each Table 1 tree's
benchmark, predicted
proposals, fit on (FitSettings()), w28, 312x96, one thread, as the bench runs it (edit_benchmark._source_scene);
saves each scene's object table, semantic map and meta to OUT/<seed>_<key>.pt, and CPU seconds per frame."""
import json
import os
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
models = Models.from_checkpoints(semantic=f"{R}/semantic/checkpoints/inference.pt",
                                 geometric=f"{R}/geometric/checkpoints/inference.pt")
out = sys.argv[1]
os.makedirs(out, exist_ok=True)
keys = os.environ.get("KEYS", "").split()
for tree in sys.argv[2:]:
    seed = tree.rstrip("/").split("_")[-1]
    records = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}
    bench = json.load(open(f"{tree}/vkitti_edit_benchmark.json"))
    sources = {f"vkitti1/{e['world']}/{e['topic']}/{e['source']}" for e in bench}  # the bench's source frames
    for key in sorted(sources & set(records)):
        if keys and key not in keys:
            continue
        rec = records[key]
        frame = load_frame(rec, (312, 96), semantic=False, instances=False)
        gt, photo = ground_truth(rec, (312, 96)), frame_photo(rec, (312, 96))
        t = time.process_time()
        scene = derender(frame.image, frame.intrinsics, models, "semantic", gt, fit=FitSettings(), photo=photo)
        cpu = time.process_time() - t
        o = scene.objects
        torch.save({"table": {k: getattr(o, k) for k in ("instance_id", "template_id", "phi", "dims", "ry", "location",
                                                         "code", "mask", "has_mask", "observed")},
                    "semantic": scene.semantic, "meta": scene.meta},
                   f"{out}/{seed}_{key.replace('/', '_')}.pt")
        joined = [f["joined_from"] for f in scene.meta.get("fits", []) if f.get("joined_from")]
        print(json.dumps({"seed": seed, "key": key, "cpu_s": round(cpu, 3), "objects": len(o.instance_id),
                          "joined": joined}), flush=True)
