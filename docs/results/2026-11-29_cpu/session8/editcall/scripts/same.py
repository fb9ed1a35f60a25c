# ruff: noqa: E501
"""Compare two saved fit results: bit-identical per field, else the largest difference."""
import sys

import torch

a, b = torch.load(sys.argv[1]), torch.load(sys.argv[2])
for k in a:
    same = torch.equal(a[k], b[k])
    print(k, "identical" if same else f"differs: max |diff| {float((a[k].double() - b[k].double()).abs().max()):.3g}, {int((a[k] != b[k]).sum())} entries")
