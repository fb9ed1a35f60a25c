# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""cmp_lt.py TAG SEEDS...: flips of rows gt_fit and pred_fit, main (cut_S.json, pred_S.json) against variant TAG
(TAG_S.json), per tree and pooled, with fixes and breaks by car (in /tmp/s34)."""
import json, sys
tag, seeds = sys.argv[1], sys.argv[2:]
G = "fit, oracle: ground-truth masks + boxes"; P = "fit, predicted proposals"
tot = {G: [0, 0, 0, 0, 0], P: [0, 0, 0, 0, 0]}
for s in seeds:
    main = {G: {(r["frame"], r["id"]): r for r in json.load(open(f"/tmp/s34/cut_{s}.json"))},
            P: {(r["frame"], r["id"]): r for r in json.load(open(f"/tmp/s34/pred_{s}.json"))["objects"][P]}}
    var = json.load(open(f"/tmp/s34/{tag}_{s}.json"))["objects"]
    for row in (G, P):
        v = {(r["frame"], r["id"]): r for r in var[row]}
        a, b = main[row], v
        keys = sorted(set(a) & set(b))
        fa = sum(a[k]["yaw_deg"] > 90 for k in keys); fb = sum(b[k]["yaw_deg"] > 90 for k in keys)
        fix = sum(a[k]["yaw_deg"] > 90 and b[k]["yaw_deg"] <= 90 for k in keys)
        brk = sum(a[k]["yaw_deg"] <= 90 and b[k]["yaw_deg"] > 90 for k in keys)
        print(f"{s} {row[:12]}: n {len(keys)} main {fa} {tag} {fb} fixes {fix} breaks {brk}")
        for i, x in enumerate((len(keys), fa, fb, fix, brk)): tot[row][i] += x
for row, t in tot.items():
    print(f"pooled {row}: n {t[0]} main {t[1]} ({100*t[1]/t[0]:.1f} %) {tag} {t[2]} ({100*t[2]/t[0]:.1f} %) fixes {t[3]} breaks {t[4]}")
