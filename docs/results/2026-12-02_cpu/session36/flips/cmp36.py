# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""cmp36.py DIR BASE_TAG VAR_TAG SEEDS...: flips (> 90 degrees) of rows gt_fit and pred_fit, BASE against VAR
(DIR/TAG_SEED.json or .json.gz, benchmarks/pose_table.py outputs), per tree and pooled, fixes and breaks by car."""
import json, sys

def load(d, tag, s):
    """DIR/TAG_SEED.json, or its .json.gz."""
    import gzip, os
    p = f"{d}/{tag}_{s}.json"
    return json.load(open(p)) if os.path.exists(p) else json.load(gzip.open(p + ".gz", "rt"))
d, a_tag, b_tag, seeds = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}
tot = {k: [0, 0, 0, 0, 0] for k in ROWS}
for s in seeds:
    A = load(d, a_tag, s)["objects"]; B = load(d, b_tag, s)["objects"]
    for short, row in ROWS.items():
        a = {(r["frame"], r["id"]): r for r in A[row]}; b = {(r["frame"], r["id"]): r for r in B[row]}
        keys = sorted(set(a) & set(b))
        fa = sum(a[k]["yaw_deg"] > 90 for k in keys); fb = sum(b[k]["yaw_deg"] > 90 for k in keys)
        fix = [k for k in keys if a[k]["yaw_deg"] > 90 and b[k]["yaw_deg"] <= 90]
        brk = [k for k in keys if a[k]["yaw_deg"] <= 90 and b[k]["yaw_deg"] > 90]
        print(f"{s} {short}: n {len(keys)} {a_tag} {fa} {b_tag} {fb} fixes {len(fix)} breaks {len(brk)}" + (f" fixed {fix}" if fix and short == 'gt_fit' else "") + (f" broken {brk}" if brk and short == 'gt_fit' else ""))
        for i, x in enumerate((len(keys), fa, fb, len(fix), len(brk))): tot[short][i] += x
for short, t in tot.items():
    print(f"pooled {short}: n {t[0]} {a_tag} {t[1]} ({100*t[1]/max(t[0],1):.1f} %) {b_tag} {t[2]} ({100*t[2]/max(t[0],1):.1f} %) fixes {t[3]} breaks {t[4]}")
