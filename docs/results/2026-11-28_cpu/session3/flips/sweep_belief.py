"""Offline sweep of the fit's final choice on a recorded capture (diagnose.py --all on val13): the belief (start cos,
MultiBin bins, net yaw; with or without ignoring the lamps' absence on border-cut cars) x facing_tie. Ad hoc; paths
under /tmp as run on 2026-11-28."""

import json
import sys

import numpy as np
import torch

sys.path.insert(0, "/work/wt/s3-flips/src")
from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.lamps import LampCue

rows = json.load(open(sys.argv[1]))


def score(r, ry, variant):
    a = r["appearance"]
    if a is None:
        return np.cos(ry - 0)  # n/a
    vals = {k: torch.tensor([v]) for k, v in a.items()}
    if variant == "start":
        return None
    app = dict(vals)
    if not variant.get("void", True):
        app["cut_left"] = torch.tensor([False])
        app["cut_right"] = torch.tensor([False])
    f = facing_belief(app, LampCue(), bins=variant["bins"])
    return f(torch.tensor([ry]))[0].numpy()


def choose(loss, b, rv, ft, tie=0.1):
    best = loss.min()
    agree = b >= rv
    ba = loss[agree].min() if agree.any() else np.inf
    if ba <= best * (1 + ft):
        pool = agree
        ref = ba
    else:
        pool = np.ones_like(agree)
        ref = best
    eq = pool & (loss <= ref * (1 + tie))
    return int(np.argmax(np.where(eq, b, -np.inf)))


variants = {
    "start(cos to ry0)": "start",
    "bins,void": {"bins": True, "void": True},
    "yaw,void": {"bins": False, "void": True},
    "bins,novoid": {"bins": True, "void": False},
    "yaw,novoid": {"bins": False, "void": False},
}
pre = {}
for name, v in variants.items():
    bs = []
    rvs = []
    for r in rows:
        ry = np.array([h["ry"] for h in r["fine"]])
        if v == "start":
            b = np.array([h["cos"] for h in r["fine"]])
            rv = -b
        else:
            b = score(r, ry, v)
            rv = score(r, ry + np.pi, v)
        bs.append(b)
        rvs.append(rv)
    pre[name] = (bs, rvs)
out = {}
for name in variants:
    for ft in [0, 0.25, 0.5, 1.0, 1e9]:
        errs = []
        tok = []
        picks = []
        for r, b, rv in zip(rows, *pre[name], strict=False):
            loss = np.array([h["loss"] for h in r["fine"]])
            k = choose(loss, b, rv, ft)
            errs.append(r["fine"][k]["ry_err"])
            tok.append(r["fine"][k]["template_ok"])
        e = np.array(errs)
        fl = e > 90
        tr = np.array([r["truncated"] for r in rows])
        print(
            "%-18s ft=%-5g flips %2d (%.1f%%) trunc %d median %.2f p90 %.1f tmpl %.1f%%"  # noqa: UP031
            % (
                name,
                ft,
                fl.sum(),
                100 * fl.mean(),
                (fl & tr).sum(),
                np.median(e),
                np.percentile(e, 90),
                100 * np.mean(tok),
            )
        )
        out[(name, ft)] = e
import pickle  # noqa: E402

pickle.dump(out, open("/tmp/s3flips/sim2.pkl", "wb"))
