"""Paired ratio this/session_start of photo_latency --json runs (wall and CPU per edit), 10k bootstrap."""
import json
import sys

import numpy as np

for t in (2,):
    runs = sorted(__import__("glob").glob(f"t{t}_r*.json"))
    for col, name in ((1, "wall"), (2, "CPU")):
        a, b, kinds = [], [], []
        for f in runs:
            d = json.load(open(f))
            a += [e[col] for e in d["this:rays"]]
            b += [e[col] for e in d["session_start:rays"]]
            kinds += [e[0] for e in d["this:rays"]]
        a, b = np.array(a), np.array(b)
        r = np.log(a / b)
        rng = np.random.default_rng(0)
        boots = [np.exp(r[rng.integers(0, len(r), len(r))].mean()) for _ in range(10000)]
        lo, hi = np.percentile(boots, [2.5, 97.5])
        print(f"threads {t} {name}: {len(runs)} runs x 14 edits, median this {np.median(a):.0f} ms, "
              f"session_start {np.median(b):.0f} ms; geometric-mean ratio {np.exp(r.mean()):.3f} [{lo:.3f}, {hi:.3f}], "
              f"faster in {(a < b).sum()} of {len(a)}")
        for k in sorted(set(kinds)):
            m = np.array([x == k for x in kinds])
            print(f"    {k}: median this {np.median(a[m]):.0f}, start {np.median(b[m]):.0f}, "
                  f"ratio {np.exp(r[m].mean()):.3f}")
sys.exit(0)
