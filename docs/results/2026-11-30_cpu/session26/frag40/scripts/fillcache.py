"""fillcache.py RAW.pt MAIN_CACHE VARIANT_CACHE GROUPING_JSON: copy main's de-rendered source scenes (dbench.py's
cache files) into a variant's cache for the frames whose proposals the variant's grouping leaves unchanged (the
instance maps main's and the variant's grouping make from raw.py's saved outputs are equal), so that only the frames
whose proposals changed are de-rendered again (each takes ~40 s on the shared machine). A scene depends on the code
only through its proposals here (the variant changes the grouping alone). Prints the changed frames.
Run with PYTHONPATH=<this branch>/src."""
import glob
import json
import os
import shutil
import sys

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS


def group(fr: dict, things: list[int], g: dict) -> torch.Tensor:
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things,
                          thing_odds=g["thing_odds"], threshold=g["center_threshold"], nms_kernel=g["nms_kernel"],
                          top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                          part_separation=g["part_separation"], merge_reach=g["merge_reach"],
                          merge_separation=g["merge_separation"])[0][0]


raw_path, main_cache, var_cache, grouping = sys.argv[1:5]
raw = torch.load(raw_path, weights_only=False)
base = {**GROUPING_DEFAULTS, "merge_reach": None}
variant = {**GROUPING_DEFAULTS, **json.loads(grouping)}
changed = {k for k, fr in raw["frames"].items()
           if not torch.equal(group(fr, raw["things"], base), group(fr, raw["things"], variant))}
os.makedirs(var_cache, exist_ok=True)
copied = 0
for path in glob.glob(f"{main_cache}/*.pt"):
    source = torch.load(path, weights_only=False).meta["source"]
    target = os.path.join(var_cache, os.path.basename(path))
    if source not in changed and not os.path.exists(target):
        shutil.copyfile(path, f"{target}.copy")
        os.replace(f"{target}.copy", target)
        copied += 1
print(f"{raw_path}: {len(changed)} frames changed {sorted(changed)}; {copied} scenes copied from main")
