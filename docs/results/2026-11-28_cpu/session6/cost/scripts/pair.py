# ruff: noqa: E402, E501, E701, E702, E401, E731, F401
"""Paired comparison of two evalfit/pose_table outputs: flips, median yaw, template, sil_iou (bootstrap 95 %)."""
import json
import sys

import numpy as np


def load(p):
    d = json.load(open(p))
    objs = d["objects"]
    if isinstance(objs, dict): objs = objs[next(k for k in objs if k.startswith("fit"))]
    return {(o["frame"], o["id"]): o for o in objs}
A, B = load(sys.argv[1]), load(sys.argv[2])
keys = sorted(set(A) & set(B))
rng = np.random.default_rng(0); idx = rng.integers(0, len(keys), (10000, len(keys)))
ci = lambda v: [round(float(np.percentile(v, 2.5)), 3), round(float(np.percentile(v, 97.5)), 3)]
out = {"n": len(keys)}
ya = np.array([A[k]["yaw_deg"] for k in keys]); yb = np.array([B[k]["yaw_deg"] for k in keys])
out["median_yaw"] = [round(float(np.median(ya)), 2), round(float(np.median(yb)), 2), ci(np.median(yb[idx], 1) - np.median(ya[idx], 1))]
fa, fb = (ya > 90).astype(float), (yb > 90).astype(float)
out["flips"] = [int(fa.sum()), int(fb.sum()), ci(100 * (fb[idx] - fa[idx]).mean(1)), "fixed", int(((fa == 1) & (fb == 0)).sum()), "broken", int(((fa == 0) & (fb == 1)).sum())]
ta = np.array([A[k]["template_ok"] for k in keys], float); tb = np.array([B[k]["template_ok"] for k in keys], float)
out["template_pct"] = [round(100 * ta.mean(), 1), round(100 * tb.mean(), 1), ci(100 * (tb[idx] - ta[idx]).mean(1)), "won", int(((ta == 0) & (tb == 1)).sum()), "lost", int(((ta == 1) & (tb == 0)).sum())]
if all(A[k].get("sil_iou") is not None and B[k].get("sil_iou") is not None for k in keys):
    ia = np.array([A[k]["sil_iou"] for k in keys]); ib = np.array([B[k]["sil_iou"] for k in keys])
    out["sil_iou"] = [round(float(ia.mean()), 4), round(float(ib.mean()), 4), ci((ib[idx] - ia[idx]).mean(1)), "better", int((ib > ia + 1e-3).sum()), "worse", int((ib < ia - 1e-3).sum())]
for name in ("dist", "scale"):
    a = np.array([A[k][name] for k in keys]); b = np.array([B[k][name] for k in keys])
    out[name] = [round(float(np.median(a)), 4), round(float(np.median(b)), 4), ci(np.median(b[idx], 1) - np.median(a[idx], 1))]
print(json.dumps(out))
