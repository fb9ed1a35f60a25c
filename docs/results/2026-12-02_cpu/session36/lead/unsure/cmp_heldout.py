# ruff: noqa: E401, E501, E701, E702, E731, I001
"""cmp_heldout.py DIR SEED...: pred_fit per object, main against ign37 (heldout.sh's outputs DIR/{main,ign37}_SEED.json):
per tree and pooled, matched cars, their median / p90 yaw error, flips (unmatched counted), fixed / broken, with a
bootstrap 95 % interval over frames of the pooled flip rates."""
import json, sys, statistics as st, random
import numpy as np
D, seeds = sys.argv[1], sys.argv[2:]
def load(v, s):
    return {(o["frame"], o["id"]): o for o in json.load(open(f"{D}/{v}_{s}.json"))["objects"]["fit, predicted proposals"]}
flip = lambda o: (not o["matched"]) or o["yaw_deg"] > 90
pool = {"main": [], "ign37": []}; fx = br = 0
print("| tree | cars | main: flips, matched median / p90 yaw | ign37: flips, matched median / p90 yaw | fixed / broken |")
print("|---|---|---|---|---|")
for s in seeds:
    a, b = load("main", s), load("ign37", s)
    f, r = sum(flip(a[k]) and not flip(b[k]) for k in a), sum(flip(b[k]) and not flip(a[k]) for k in a)
    fx += f; br += r
    cells = []
    for v, d in (("main", a), ("ign37", b)):
        pool[v] += [(s, k, d[k]) for k in a]
        y = [o["yaw_deg"] for o in d.values() if o["matched"]]
        cells.append(f"{sum(map(flip, d.values()))} ({100 * sum(map(flip, d.values())) / len(d):.1f} %), {st.median(y):.2f} / {np.percentile(y, 90):.1f}")
    print(f"| {s} | {len(a)} | {cells[0]} | {cells[1]} | {f} / {r} |")
frames = sorted({(s, k[0]) for s, k, _ in pool["main"]}); rnd = random.Random(0)
def rate(v, fr):
    by = {}
    for s, k, o in pool[v]: by.setdefault((s, k[0]), []).append(flip(o))
    xs = [x for f in fr for x in by[f]]; return 100 * sum(xs) / len(xs)
cells = []
for v in ("main", "ign37"):
    boots = sorted(rate(v, rnd.choices(frames, k=len(frames))) for _ in range(1000))
    y = [o["yaw_deg"] for _, _, o in pool[v] if o["matched"]]
    cells.append(f"{sum(flip(o) for _, _, o in pool[v])} ({rate(v, frames):.1f} % [{boots[25]:.1f}, {boots[974]:.1f}]), {st.median(y):.2f} / {np.percentile(y, 90):.1f}")
print(f"| **pooled** | {len(pool['main'])} | {cells[0]} | {cells[1]} | **{fx} / {br}** |")
