# ruff: noqa: E402, E501, E701, E702
# ruff: noqa
"""budget.py TREE OUT.json [bench overrides...]: the turns' error on the car's target pixels split by the photo
appearance's source code (ground-truth geometry oracle), per angle bin: share of pixels and share of squared error."""
import sys, json, torch
import sdn3d.evaluation.counterfactual as C
from sdn3d.editing.photo.settings import SOURCE_NAMES
calls = []
o_psnr = C._psnr_l1
def psnr(pred, target, mask):
    calls.append((pred, target, mask))
    return o_psnr(pred, target, mask)
C._psnr_l1 = psnr
rows = []
o_shares = C._shares
def shares(source, mask):
    for pred, target, m in calls[::-1]:
        if m is mask:
            err = ((pred - target) ** 2).sum(0)  # (H, W)
            src = source.long()
            out = {}
            for k, name in enumerate(SOURCE_NAMES):
                sel = mask & (src == k)
                if sel.any():
                    out[name] = [int(sel.sum()), float(err[sel].sum())]
            rows.append({"pixels": int(mask.sum()), "sse": float(err[mask].sum()), "by": out})
            break
    calls.clear()
    return o_shares(source, mask)
C._shares = shares
o_score = C._score_pair
def score(result, pair, *a, **k):
    n = len(rows)
    o_score(result, pair, *a, **k)
    for r in rows[n:]:
        r.update(bin=result.bin if hasattr(result, "bin") else None, key=str(pair.key), angle=getattr(pair, "angle_deg", None), source=result.source)
C._score_pair = score
from sdn3d.cli.bench import main
tree, out = sys.argv[1], sys.argv[2]
main([f"counterfactual=true", f"data.root={tree}", f"output_dir={out}_bench", "counterfactual_fills=[auto]",
      "counterfactual_kinds=[turn]", "counterfactual_sources=[oracle]", "examples=0", *sys.argv[3:]])
json.dump(rows, open(out, "w"))
import collections
agg = collections.defaultdict(lambda: collections.defaultdict(lambda: [0, 0.0]))
tot = collections.defaultdict(lambda: [0, 0.0])
for r in rows:
    a = r["angle"]
    tot[a][0] += r["pixels"]; tot[a][1] += r["sse"]
    for name, (p, s) in r["by"].items():
        agg[a][name][0] += p; agg[a][name][1] += s
for a in sorted(agg, key=float):
    P, S = tot[a]
    print(f"turn {a}: n_pairs={sum(1 for r in rows if r['angle']==a)} pixels={P} mean sq err/px={S/P/3:.4f}")
    for name, (p, s) in sorted(agg[a].items(), key=lambda kv: -kv[1][1]):
        print(f"   {name:12s} pixels {100*p/P:5.1f} %  error {100*s/S:5.1f} %  mse/px {s/max(p,1)/3:.4f}")
