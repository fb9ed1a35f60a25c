"""rawgt.py TREE CACHE OUT.pt: the part of join40's raw.py file census.py reads, without running the network: for
every predicted scene of CACHE (dcache.py), the frame's ground-truth instance map at 312x96 (an ORACLE, only to
score), with the thing classes (Car 12, Van 13) and the size. Session 28 merge40."""
import glob
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records

tree, cache, out = sys.argv[1:4]
records = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}
frames = {}
for p in glob.glob(f"{cache}/*.pt"):
    s = torch.load(p, weights_only=False)
    if s.meta.get("proposals") == "semantic":
        frames[s.meta["source"]] = {"gt_instances": ground_truth(records[s.meta["source"]], (312, 96)).instances}
torch.save({"tree": tree, "size": (312, 96), "things": [12, 13], "frames": frames}, out)
print(out, len(frames), "frames")
