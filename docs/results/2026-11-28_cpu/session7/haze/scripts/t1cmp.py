# ruff: noqa: E402, E501, E701, E702
"""t1cmp.py DIR TAG_A TAG_B TREE[,TREE...] SRC: Table 1 photo rows, 3D-SDN's own PSNR on the edit region ("all"),
TAG_A minus TAG_B paired per entry over the trees, overall and per kind x weather: mean [95% bootstrap, 10k], wins/losses (n)."""
import json
import sys

import numpy as np

d, a_tag, b_tag, trees, src = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4].split(","), sys.argv[5]
rng = np.random.default_rng(0)


def load(p):
    r = json.load(open(p)); out = {}
    for s, es in r["entries"].items():
        for i, e in enumerate(es):
            m = ((e.get("metrics") or {}).get("photo") or {}).get("3d-sdn")
            if m: out[(s, e.get("id", i))] = (e.get("edit_kind"), m["all"]["psnr"], e["key"].split()[0].split("/")[1])
    return out


def ci(x):
    x = np.asarray(x)
    if not len(x): return None
    bt = x[rng.integers(0, len(x), (10000, len(x)))].mean(1)
    return [float(x.mean()), float(np.percentile(bt, 2.5)), float(np.percentile(bt, 97.5)), int((x > 1e-9).sum()), int((x < -1e-9).sum()), len(x)]


def fmt(c): return f"{c[0]:+.2f} [{c[1]:+.2f}, {c[2]:+.2f}] {c[3]}/{c[4]} (n={c[5]})"


rows = []
for t in trees:
    a, b = load(f"{d}/{t}_{a_tag}_{src}/results.json"), load(f"{d}/{t}_{b_tag}_{src}/results.json")
    rows += [(a[k][0], a[k][2], a[k][1] - b[k][1]) for k in a if k in b]
out = {"all": ci([r[2] for r in rows])}
print(f"{a_tag} - {b_tag}, {src}, trees {','.join(trees)}: all {fmt(out['all'])}")
for kind in sorted({r[0] for r in rows}):
    c = ci([r[2] for r in rows if r[0] == kind]); out[kind] = {"all": c}
    print(f"  {kind}: {fmt(c)}")
    for w in sorted({r[1] for r in rows}):
        c = ci([r[2] for r in rows if r[0] == kind and r[1] == w])
        if c: out[kind][w] = c; print(f"    {w}: {fmt(c)}")
if len(sys.argv) > 6: json.dump(out, open(sys.argv[6], "w"), indent=1)
