# ruff: noqa: E501
"""floor.py TREE OUT.json: the floor of Table 1: the unedited source image itself as the edit, scored against each
entry's target with the bench's own code (edit_regions, region_metrics: 'all', 'largest', 'objects' and 'whole'
regions, 312x96, the same load_frame resize as sdn3d-bench). One record per entry with operations. Session 30
t1big30. Run with PYTHONPATH=<plain tree>/src."""
import json
import os
import sys

import torch

from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.frames import load_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import _instances, edit_kind, edit_regions, index_records, region_metrics

tree, out = sys.argv[1], sys.argv[2]
size = (312, 96)
records = index_records(read_frames(tree))
rows = []
for i, e in enumerate(load_edit_benchmark(os.path.join(tree, "vkitti_edit_benchmark.json"))):
    if not e.operations:
        continue
    source, target = records[(e.world, e.variation, e.source_frame)], records[(e.world, e.variation, e.target_frame)]
    src = load_frame(source, size, semantic=False, instances=False).image
    tgt = load_frame(target, size, semantic=False, instances=False).image
    regions, box, gt_ids = edit_regions(e, source, target, size)
    objects = torch.isin(_instances(target, size), torch.tensor(gt_ids, dtype=torch.long))
    rows.append({"index": i, "edit_kind": edit_kind(e), "metrics": region_metrics(src, tgt, regions, box, None, objects)})
json.dump(rows, open(out, "w"))
print(tree, len(rows))
