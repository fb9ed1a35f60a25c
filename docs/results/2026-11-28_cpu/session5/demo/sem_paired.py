"""Paired comparison of two sem_eval.py results per variation: the proposals' recall (found / objects over the same
frames), its change with a 95 % bootstrap interval over frames (10,000 draws, seed 0), and the frames where the second
found more / fewer of the cars.

    python sem_paired.py BEFORE.json AFTER.json
"""
import json
import sys

import numpy as np

before, after = (json.load(open(p)) for p in sys.argv[1:3])
out = {}
for var in (v for v in before if not v.startswith("_")):
    b = {f["key"]: f for f in before[var]["per_frame"]}
    a = {f["key"]: f for f in after[var]["per_frame"]}
    keys = sorted(set(a) & set(b))
    n = np.array([b[k]["objects"] for k in keys], dtype=float)
    fb = np.array([b[k]["found"] for k in keys], dtype=float)
    fa = np.array([a[k]["found"] for k in keys], dtype=float)
    idx = np.random.default_rng(0).integers(0, len(keys), size=(10_000, len(keys)))
    diff = fa[idx].sum(1) / n[idx].sum(1).clip(1) - fb[idx].sum(1) / n[idx].sum(1).clip(1)
    out[var] = {"frames": len(keys), "objects": int(n.sum()), "recall_before": round(fb.sum() / n.sum(), 3),
                "recall_after": round(fa.sum() / n.sum(), 3), "change": round((fa.sum() - fb.sum()) / n.sum(), 3),
                "change_ci95": [round(float(np.percentile(diff, q)), 3) for q in (2.5, 97.5)],
                "frames_more_found": int((fa > fb).sum()), "frames_fewer_found": int((fa < fb).sum()),
                "miou_before": before[var]["miou"], "miou_after": after[var]["miou"]}
print(json.dumps(out, indent=1))
