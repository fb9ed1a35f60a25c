# ruff: noqa: E501, E701, E702
"""vpm_cmp.py A.json B.json [TELEA.json]: deletes, photo:rays PSNR on the vacated region + shadow band, B - A paired (10k bootstrap), per weather; with TELEA.json also B - Telea."""
import json
import sys

import numpy as np


def load(p):
    return {q["key"]: q["metrics"] for q in json.load(open(p))["pairs"] if q["kind"] == "delete"}
a, b = load(sys.argv[1]), load(sys.argv[2]); t = load(sys.argv[3]) if len(sys.argv) > 3 else None
rng = np.random.default_rng(0)
def ci(d):
    d = np.asarray(d); bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] {int((d > 1e-6).sum())}/{int((d < -1e-6).sum())} (n={len(d)})"
keys = sorted(set(a) & set(b))
for v in ["all"] + sorted({k.split("/")[1] for k in keys}):
    ks = [k for k in keys if v == "all" or k.split("/")[1] == v]
    line = f"{v:6s} new - old: " + ci([b[k]["photo:rays"]["hole"]["psnr"] - a[k]["photo:rays"]["hole"]["psnr"] for k in ks])
    line += f"; new {np.mean([b[k]['photo:rays']['hole']['psnr'] for k in ks]):.2f}"
    if t: line += "; new - Telea: " + ci([b[k]["photo:rays"]["hole"]["psnr"] - t[k]["photo:telea"]["hole"]["psnr"] for k in ks])
    print(line)
