"""Offline check that the pairwise end-for-end rule (fit._choose at 01b3dbd) chooses what the first rule chose on the
val13 capture, for facing_tie x FACING_MARGIN. Ad hoc; paths under /tmp as run on 2026-11-28."""

import json
import math

import numpy as np

rows = json.load(open("/tmp/s3flips/val13_capture2.json"))


def choose_pair(loss, b, ry, ft, margin, tie=0.1, axis=math.cos(math.radians(30))):
    d = ry[:, None] - ry[None, :]
    opposite = np.cos(d) < -axis
    more = (b[None, :] - b[:, None]) >= margin  # h' (col) believed more than h (row) by margin
    close = loss[None, :] <= loss[:, None] * (1 + ft)
    beaten = (opposite & more & close).any(1)
    pool = ~beaten
    ref = loss[pool].min()
    eq = pool & (loss <= ref * (1 + tie))
    return int(np.argmax(np.where(eq, b, -np.inf)))


for ft in [0, 0.25, 0.5, 1.0]:
    for margin in [0, 0.25, 0.5, 1.0]:
        errs = []
        tok = []
        for r in rows:
            loss = np.array([h["loss"] for h in r["fine"]])
            b = np.array([h["cos"] for h in r["fine"]])
            ry = np.array([h["ry"] for h in r["fine"]])
            k = choose_pair(loss, b, ry, ft, margin)
            errs.append(r["fine"][k]["ry_err"])
            tok.append(r["fine"][k]["template_ok"])
        e = np.array(errs)
        fl = e > 90
        print(
            "ft=%-4g margin=%-4g flips %2d (%.1f%%) median %.2f p90 %.1f tmpl %.1f%%"  # noqa: UP031
            % (ft, margin, fl.sum(), 100 * fl.mean(), np.median(e), np.percentile(e, 90), 100 * np.mean(tok))
        )
