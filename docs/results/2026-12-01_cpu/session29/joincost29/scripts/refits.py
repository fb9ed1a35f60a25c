"""refits.py: for each joined tuning frame, the proposals each fit call of the branch's de-render fits (the first
pass, then the second) and why a kept proposal was fitted again (its prediction's bits, or its ignored pixels in its
windows); session 29 joincost29."""
import os
import sys

import sdn3d.derender as D

T = "/tmp/s28/merge40/trees"
sys.argv = ["derun.py", "/tmp/s29/joincost29/refits_out", f"{T}/t1_11", f"{T}/t1_37"]
os.environ["KEYS"] = "vkitti1/0001/clone/00034 vkitti1/0001/rain/00034 vkitti1/0001/rain/00037"
real_fit, real_same = D.fit_proposals, D._same_prediction


def fit(intr, masks, ids, rows, *a, **k):
    print("  fits", ids[rows].tolist(), file=sys.stderr)
    return real_fit(intr, masks, ids, rows, *a, **k)


def same(predicted, appearance, earlier):
    out = real_same(predicted, appearance, earlier)
    print("  prediction bits changed:", (~out).nonzero().flatten().tolist(), "(rows)", file=sys.stderr)
    return out


D.fit_proposals, D._same_prediction = fit, same
exec(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "derun.py")).read())
