"""compare.py A B: every scene file of A against B's (derun.py's output): object table tensors, semantic map, meta;
prints one line per frame (bit-equal or the largest difference) and a summary."""
import glob
import os
import sys

import torch


def diff(a, b, path=""):
    """list of (path, what) where a and b differ; tensors bit for bit (NaN equal to NaN)."""
    if isinstance(a, torch.Tensor):
        if not isinstance(b, torch.Tensor) or a.shape != b.shape or a.dtype != b.dtype:
            return [(path, "shape/dtype")]
        if torch.equal(a, b) or (a.is_floating_point()
                                 and torch.equal(torch.nan_to_num(a, 7.0), torch.nan_to_num(b, 7.0))):
            return []
        d = (a.double() - b.double()).abs().max().item() if a.is_floating_point() else "int/bool differs"
        return [(path, f"max |diff| {d}")]
    if isinstance(a, dict):
        if not isinstance(b, dict) or set(a) != set(b):
            return [(path, f"keys {sorted(set(a) ^ set(b or {}))}")]
        return [x for k in a for x in diff(a[k], b[k], f"{path}.{k}")]
    if isinstance(a, (list, tuple)):
        if not isinstance(b, (list, tuple)) or len(a) != len(b):
            return [(path, "length")]
        return [x for i, (u, v) in enumerate(zip(a, b, strict=True)) for x in diff(u, v, f"{path}[{i}]")]
    return [] if a == b else [(path, f"{a!r} != {b!r}")]


A, B = sys.argv[1:3]
n = same = objects = 0
for pa in sorted(glob.glob(f"{A}/*.pt")):
    pb = f"{B}/{os.path.basename(pa)}"
    if not os.path.exists(pb):
        continue
    a, b = torch.load(pa, weights_only=False), torch.load(pb, weights_only=False)
    d = diff(a, b)
    n += 1
    same += not d
    objects += len(a["table"]["instance_id"])
    joined = [f["joined_from"] for f in a["meta"].get("fits", []) if f.get("joined_from")]
    if d or joined or os.environ.get("ALL"):
        print(os.path.basename(pa), "joined" if joined else "", "bit-equal" if not d else d[:8])
print(f"{same} of {n} frames bit-equal ({objects} objects)")
