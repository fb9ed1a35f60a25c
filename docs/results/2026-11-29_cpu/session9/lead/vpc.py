# ruff: noqa: E501, E701, E702
"""vpc.py TAG_A TAG_B: deletes, photo:rays PSNR (vacated + shadow band) B - A paired per variation, and VP heading error per variation (truth: clone/fog/rain 0, X-deg-right -X, X-deg-left +X)."""
import json
import sys

import numpy as np

D = "/tmp/s9data/lead/vp_"
def load(t):
    ps = [q for q in json.load(open(D + t + "/counterfactual.json"))["pairs"] if q["kind"] == "delete"]
    import os
    hs = [float(x) for x in open(D + t + ".vplog")] if os.path.exists(D + t + ".vplog") and os.path.getsize(D + t + ".vplog") else [float("nan")] * len(ps)
    assert len(ps) == len(hs), (len(ps), len(hs))
    return {q["key"]: (q["metrics"]["photo:rays"]["hole"]["psnr"], h) for q, h in zip(ps, hs, strict=True)}
def truth(k):
    v = k.split("/")[1]
    if "deg" in v: a = float(v.split("-")[0]); return -a if "right" in v else a
    return 0.0
a, b = load(sys.argv[1]), load(sys.argv[2]); rng = np.random.default_rng(0)
def ci(d):
    d = np.asarray(d); bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] {int((d > 1e-6).sum())}/{int((d < -1e-6).sum())} (n={len(d)})"
keys = sorted(set(a) & set(b))
for v in ["all"] + sorted({k.split("/")[1] for k in keys}):
    ks = [k for k in keys if v == "all" or k.split("/")[1] == v]
    ea = np.array([abs(a[k][1] - truth(k)) for k in ks]); eb = np.array([abs(b[k][1] - truth(k)) for k in ks])
    print(f"{v:13s} PSNR B-A {ci([b[k][0] - a[k][0] for k in ks])}; A {np.mean([a[k][0] for k in ks]):.2f} B {np.mean([b[k][0] for k in ks]):.2f}; |heading err| median A {np.median(ea):.1f} B {np.median(eb):.1f}, >5deg A {int((ea>5).sum())} B {int((eb>5).sum())}")
if len(sys.argv) > 3:
    for k in keys: print(k, truth(k), round(a[k][1], 1), round(b[k][1], 1), round(b[k][0] - a[k][0], 2))
