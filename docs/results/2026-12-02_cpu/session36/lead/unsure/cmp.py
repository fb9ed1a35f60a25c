# ruff: noqa: E401, E501, E701, E702, I001
"""cmp.py TAG [TAG2]: pred_fit per object of TAG (and TAG2, else main: the flips helper's main_*.json.gz) on trees
35-43: matched cars, their median / p90 yaw error, flips among matched and among all (unmatched = flipped), and the
fixes / breaks of flips paired by frame and car."""
import gzip, json, sys, statistics as st
import numpy as np
M = "/work/main/docs/results/2026-12-02_cpu/session36/flips/tuning/main_{}.json.gz"
def load(tag, s):
    p = M.format(s) if tag == "main" else f"/tmp/s36/soft/{tag}_{s}.json"
    d = json.load(gzip.open(p) if p.endswith(".gz") else open(p))
    return {(o["frame"], o["id"]): o for o in d["objects"]["fit, predicted proposals"]}
A, B = (sys.argv[1], sys.argv[2]) if len(sys.argv) > 2 else ("main", sys.argv[1])
rows = {A: [], B: []}; fx = br = 0
for s in (35, 37, 39, 41, 43):
    a, b = load(A, s), load(B, s)
    for k in a:
        fa = (not a[k]["matched"]) or a[k]["yaw_deg"] > 90; fb = (not b[k]["matched"]) or b[k]["yaw_deg"] > 90
        fx += fa and not fb; br += fb and not fa
        rows[A].append(a[k]); rows[B].append(b[k])
for t in (A, B):
    m = [o for o in rows[t] if o["matched"]]; y = [o["yaw_deg"] for o in m]
    fl = sum((not o["matched"]) or o["yaw_deg"] > 90 for o in rows[t])
    print(f"{t:8s} cars {len(rows[t])} matched {len(m)} yaw median {st.median(y):.2f} p90 {np.percentile(y, 90):.1f} flips matched {sum(v > 90 for v in y)} all {fl} ({100 * fl / len(rows[t]):.1f} %) sil_iou {np.mean([o['sil_iou'] for o in m if o['sil_iou'] is not None]):.3f} dist median {st.median(o['dist'] for o in m):.4f}")
print(f"{B} against {A}: flips fixed {fx}, broken {br}")
