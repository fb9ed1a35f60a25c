"""raw.py TREE OUT.pt: the semantic branch's raw outputs (session 21's demo weights, w0) on every source frame of a
Table 1 tree's edit benchmark at 312x96 (the size Table 1's rows de-render at), with the frame's ground-truth
instance map at that size (an oracle, for scoring only). Session 19 inst's raw.py with w0 and no flip (w0's
test_flip is False). The grouping variants are then scored offline (census.py) without running the network again.
Run: PYTHONPATH=<code>/src OMP_NUM_THREADS=1 nice -n 5 python raw.py /tmp/s21data/trees/t1_35 /tmp/.../raw35.pt"""
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.semantic.predict import SemanticPredictor

tree, out = sys.argv[1], sys.argv[2]
w, h = 312, 96
torch.set_num_threads(1)
pred = SemanticPredictor.from_checkpoint("/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt")
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
records = index_records(read_source(synth_data_source(tree)))
keys = sorted({(e.world, e.variation, e.source_frame) for e in entries})
frames = {}
with torch.no_grad():
    for k in keys:
        rec = records[k]
        img = load_frame(rec, (w, h), semantic=False, instances=False).image[None]
        o = pred.net(img)
        gt = ground_truth(rec, (w, h))
        frames[rec.key] = {"image": (img[0] * 255).round().byte(), "logits": o["logits"][0].half(),
                           "center": o["center"][0], "offset": o["offset"][0], "gt_instances": gt.instances}
torch.save({"tree": tree, "size": (w, h), "things": list(pred.thing_classes), "grouping": dict(pred.grouping),
            "frames": frames}, out)
print(out, len(frames), "frames")
