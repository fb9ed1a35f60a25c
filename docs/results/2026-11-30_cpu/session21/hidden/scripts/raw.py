# ruff: noqa: E501, E701, E702
"""raw.py (copied from session 19 inst, weights path changed) TREE W H OUT.pt: the semantic branch's raw outputs (session 21's demo weights (/tmp/s21data/demo/out)) on every source frame of a
Table 1 tree's edit benchmark, at W x H, plain and flip-averaged (semantic/tta.py), with the frame's ground-truth
semantic and instance maps at that size and each annotated object's camera distance by track id + 1 (gt_range; oracles,
for scoring only). One file per tree and size; the grouping
variants are then scored offline by census.py without running the network again."""
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.semantic.predict import SemanticPredictor
from sdn3d.semantic.tta import flip_averaged_outputs

tree, w, h, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
torch.set_num_threads(1)
CKPT = "/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt"
pred = SemanticPredictor.from_checkpoint(CKPT)
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
records = index_records(read_source(synth_data_source(tree)))
keys = sorted({(e.world, e.variation, e.source_frame) for e in entries})
frames = {}
with torch.no_grad():
    for k in keys:
        rec = records[k]
        img = load_frame(rec, (w, h), semantic=False, instances=False).image[None]
        o = pred.net(img); f = flip_averaged_outputs(pred.net, img)
        gt = ground_truth(rec, (w, h))
        frames[rec.key] = {"image": (img[0] * 255).round().byte(), "logits": o["logits"][0].half(), "center": o["center"][0], "offset": o["offset"][0],
                           "logits_flip": f["logits"][0].half(), "center_flip": f["center"][0], "offset_flip": f["offset"][0],
                           "gt_semantic": gt.semantic, "gt_instances": gt.instances,
                           "gt_range": {o.track_id + 1: float(sum(x * x for x in o.location) ** 0.5) for o in rec.objects}}
torch.save({"tree": tree, "size": (w, h), "things": list(pred.thing_classes), "grouping": dict(pred.grouping), "frames": frames}, out)
print(out, len(frames), "frames")
