# ruff: noqa: E401, E501, E701, E702, I001
"""which36.py DIR BASE_TAG VAR_TAG SEEDS... [--cut CUTDIR]: the cars of row gt_fit that VAR fixes and breaks against
BASE (DIR/TAG_SEED.json), and BASE's flips: the border that cuts the box (312 px wide: -1 left, +1 right, 0 none),
whether the truth follows right-hand traffic's rule for a cut car (right border: back, sin(alpha) < 0; left: front),
and with --cut (cutcars36.py outputs CUTDIR/cut_SEED.json, main's reading) the bins' belief 2p - 1 in the true end."""
import json, math, sys

def load(d, tag, s):
    """DIR/TAG_SEED.json, or its .json.gz."""
    import gzip, os
    p = f"{d}/{tag}_{s}.json"
    return json.load(open(p)) if os.path.exists(p) else json.load(gzip.open(p + ".gz", "rt"))
args = sys.argv[1:]
cut = None
if "--cut" in args: i = args.index("--cut"); cut = args[i + 1]; del args[i:i + 2]
d, a_tag, b_tag, seeds = args[0], args[1], args[2], args[3:]
ROW = "fit, oracle: ground-truth masks + boxes"

def side(box, width=312):
    return (box[2] > width - 1.5) - (box[0] < 0.5)

tally = {}
for s in seeds:
    A = {(r["frame"], r["id"]): r for r in load(d, a_tag, s)["objects"][ROW]}
    B = {(r["frame"], r["id"]): r for r in load(d, b_tag, s)["objects"][ROW]}
    C = {(r["frame"], r["id"]): r for r in load(cut, "cut", s)} if cut else {}
    for k in sorted(set(A) & set(B)):
        fa, fb = A[k]["yaw_deg"] > 90, B[k]["yaw_deg"] > 90
        kind = "fix" if fa and not fb else "break" if fb and not fa else "base flip" if fa else None
        if kind is None: continue
        a = A[k]; sd = side(a["box"])
        x, z = a["true_xz"]; alpha = a["true_ry"] - math.atan2(x, z)  # approx. ray through the car's centre
        rule = "-" if sd == 0 else ("follows" if (sd > 0) == (math.sin(alpha) < 0) else "against")
        c = C.get(k)
        net = f" net(true) {c['net_true']:+.2f} lamps(true) {c['lamps_true']:+.2f} usable {c['lamp_usable']} present {c['lamp_present']}" if c else ""
        print(f"{s} {kind:9s} {k[0]} {k[1]} side {sd:+d} rule {rule:7s} {a_tag} {a['yaw_deg']:6.1f} {b_tag} {B[k]['yaw_deg']:6.1f} px {a['pixels']}{net}")
        key = (kind, "cut" if sd else "whole", rule)
        tally[key] = tally.get(key, 0) + 1
for k, v in sorted(tally.items()): print(*k, v)
