# ruff: noqa: INP001, E501
"""groups.py A B: B minus A on 3D-SDN's PSNR all, per group of edited cars (the 12 largest sums)."""
import json
import sys
from collections import defaultdict

import numpy as np


def load(folder):
    (entries,) = json.load(open(folder + "/results.json"))["entries"].values()
    return {r["index"]: r for r in entries}


a, b = load(sys.argv[1]), load(sys.argv[2])
by = defaultdict(list)
for k in a:
    by[" ".join(a[k]["cars"])].append(b[k]["metrics"]["photo"]["3d-sdn"]["all"]["psnr"]
                                      - a[k]["metrics"]["photo"]["3d-sdn"]["all"]["psnr"])
for cars, v in sorted(by.items(), key=lambda x: -abs(np.sum(x[1])))[:12]:
    print(f"{cars:40s} {len(v):3d} {np.mean(v):+.2f}")
