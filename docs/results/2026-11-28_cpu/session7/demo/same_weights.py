# ruff: noqa: E402, E501, E701, E702
"""Compare the weights of two checkpoints: identical bit for bit, else the largest difference. Usage: same_weights.py A B"""
import sys

import torch

a, b = (torch.load(p, map_location="cpu", weights_only=False)["state_dict"] for p in sys.argv[1:3])
if a.keys() != b.keys():
    print("different keys:", sorted(set(a) ^ set(b))[:5]); sys.exit(1)
diff = {k: float((a[k].double() - b[k].double()).abs().max()) if a[k].numel() else 0.0 for k in a if not torch.equal(a[k], b[k])}
print(f"{len(a)} tensors; identical: {len(a) - len(diff)}; different: {len(diff)}" + (f"; largest difference {max(diff.values()):.3g} ({max(diff, key=diff.get)})" if diff else ""))
