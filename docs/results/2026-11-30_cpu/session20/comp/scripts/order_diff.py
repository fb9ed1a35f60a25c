# ruff: noqa: E501, E701, E702
"""order_diff.py COMMIT RAW.pt... (run from the repository root): the part rule before the 2-means split (the
grouping of src/sdn3d/semantic/panoptic.py at COMMIT, comp's e6337c1) against the installed grouping (comp2: the split
first, on the instance as grouped, then the part rule), both with GROUPING_DEFAULTS, on the frames session 19 inst's
raw.py saved. Prints, per RAW file and pooled: frames whose instance maps differ, proposals in each, and every
annotated Car/Van over the paper's pixel filter (ground truth, an oracle for scoring only) whose best proposal IoU
differs, with both IoUs."""
import importlib.util
import subprocess
import sys
import tempfile

import torch

from sdn3d.evaluation.proposal_recall import min_pixels_at
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic import panoptic as installed
from sdn3d.semantic.predict import GROUPING_DEFAULTS

commit, paths = sys.argv[1], sys.argv[2:]
with tempfile.NamedTemporaryFile("w", suffix=".py") as f:
    f.write(subprocess.run(["git", "show", f"{commit}:src/sdn3d/semantic/panoptic.py"], capture_output=True, text=True, check=True).stdout); f.flush()
    spec = importlib.util.spec_from_file_location("panoptic_at_commit", f.name); old = sys.modules["panoptic_at_commit"] = importlib.util.module_from_spec(spec); spec.loader.exec_module(old)


def group(module, fr, things):
    g = GROUPING_DEFAULTS; prob = fr["logits"].float().softmax(0)[None]
    return module.group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                                 nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                                 part_separation=g["part_separation"])[0][0]


def best(inst, m):
    return max((int((inst == p)[m].sum()) / int(((inst == p) | m).sum()) for p in inst.unique().tolist() if p > 0), default=0.0)


total = [0, 0, 0, 0]
for path in paths:
    raw = torch.load(path, weights_only=False); things = raw["things"]; n = [0, 0, 0, 0]
    for key, fr in raw["frames"].items():
        a, b = group(old, fr, things), group(installed, fr, things)
        n[0] += 1; n[2] += a.unique().numel() - 1; n[3] += b.unique().numel() - 1
        if torch.equal(a, b): continue
        n[1] += 1; gi = fr["gt_instances"]
        for i in gi.unique().tolist():
            if i < INSTANCE_DIVISOR or i // INSTANCE_DIVISOR not in things: continue
            m = gi == i
            if int(m.sum()) <= min_pixels_at(*raw["size"]): continue
            ia, ib = best(a, m), best(b, m)
            if abs(ia - ib) > 1e-9: print(f"{path.split('/')[-1]} {key} car {i} area {int(m.sum())}: part rule first {ia:.3f}, split first {ib:.3f}")
    print(f"{path.split('/')[-1]}: {n[1]} of {n[0]} frames differ; proposals part rule first {n[2]}, split first {n[3]}")
    total = [t + x for t, x in zip(total, n, strict=True)]
print(f"pooled: {total[1]} of {total[0]} frames differ; proposals part rule first {total[2]}, split first {total[3]}")
