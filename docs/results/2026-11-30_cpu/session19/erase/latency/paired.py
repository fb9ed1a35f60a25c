# ruff: noqa: E501
"""paired.py [DIR]: the branch ('this:rays') against main ('main:rays') in photo_latency --json runs t1_r*.json of DIR
(default: this folder), per edit (the same edits, the codes taking turns): medians, the geometric-mean ratio
branch / main with a 10k bootstrap 95 % interval and the count of edits where the branch was faster; per kind the
medians and the ratio of medians."""

from __future__ import annotations

import glob
import json
import statistics
import sys
from pathlib import Path

import numpy as np


def main() -> int:
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent
    runs = sorted(glob.glob(str(folder / "t1_r*.json")))
    for col, name in ((1, "wall"), (2, "CPU")):
        a, b, kinds = [], [], []
        for f in runs:
            d = json.load(open(f))
            a += [e[col] for e in d["this:rays"]]
            b += [e[col] for e in d["main:rays"]]
            kinds += [e[0] for e in d["this:rays"]]
        x, y = np.array(a), np.array(b)
        r = np.log(x / y)
        rng = np.random.default_rng(0)
        boots = [np.exp(r[rng.integers(0, len(r), len(r))].mean()) for _ in range(10000)]
        lo, hi = np.percentile(boots, [2.5, 97.5])
        print(f"threads 1 {name}: {len(runs)} runs x {len(a) // max(len(runs), 1)} edits, median branch {statistics.median(a):.0f} ms, "
              f"main {statistics.median(b):.0f} ms; geometric-mean ratio {np.exp(r.mean()):.3f} [{lo:.3f}, {hi:.3f}], "
              f"branch faster in {int((x < y).sum())} of {len(a)}")
        for kind in sorted(set(kinds)):
            ka = [v for v, k in zip(a, kinds, strict=True) if k == kind]
            kb = [v for v, k in zip(b, kinds, strict=True) if k == kind]
            print(f"    {kind}: median branch {statistics.median(ka):.0f}, main {statistics.median(kb):.0f}, "
                  f"ratio {statistics.median(ka) / statistics.median(kb):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
