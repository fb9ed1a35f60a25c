# ruff: noqa
"""cmp.py BASE_DIR NEW_DIR [...]: photo:rays deletes, new minus base, PSNR on vacated + shadow band, pooled over dir pairs."""
import json, sys
import numpy as np
def load(d):
    q = json.load(open(f"{d}/counterfactual.json"))
    return {(p["source"], p["key"]): p["metrics"]["photo:rays"]["hole"]["psnr"] for p in q["pairs"] if p.get("kind") == "delete" and "photo:rays" in p.get("metrics", {})}
args = sys.argv[1:]
allb, alln = [], []
rng = np.random.default_rng(0)
for b, n in zip(args[0::2], args[1::2]):
    A, B = load(b), load(n)
    ks = sorted(set(A) & set(B))
    d = np.array([B[k] - A[k] for k in ks])
    boots = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    print(f"{n}: n={len(d)} base {np.mean([A[k] for k in ks]):.2f} new {np.mean([B[k] for k in ks]):.2f} diff {d.mean():+.3f} [{np.percentile(boots,2.5):+.3f}, {np.percentile(boots,97.5):+.3f}] {int((d>1e-6).sum())}/{int((d<-1e-6).sum())}")
    allb += [A[k] for k in ks]; alln += [B[k] for k in ks]
d = np.array(alln) - np.array(allb)
boots = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
print(f"pooled: n={len(d)} diff {d.mean():+.3f} [{np.percentile(boots,2.5):+.3f}, {np.percentile(boots,97.5):+.3f}] {int((d>1e-6).sum())}/{int((d<-1e-6).sum())}")
