"""Are two Table 1 photo-row runs of t1.sh the same? ``t1_identity.py MAIN_RUN BRANCH_RUN`` (a run folder; its
``.dump`` folder beside it).

Per entry of ``results.json``: every metric of every method equal (timings, ``latency_ms``, left out); the Table 1
file ``table1.md`` equal line by line except its latency line; each entry's ``.dump/NNNN.npz`` (the pictures: source,
target, 3D-SDN, 2D, masks, the photo path's source codes and parts) equal array by array. Prints one line per check
and the largest absolute difference where anything differs.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np


def _strip(x):
    if isinstance(x, dict):
        return {k: _strip(v) for k, v in x.items() if k != "latency_ms" and not k.endswith("_ms")}
    if isinstance(x, list):
        return [_strip(v) for v in x]
    return x


def main() -> None:
    a, b = Path(sys.argv[1]), Path(sys.argv[2])
    ra, rb = (json.loads((p / "results.json").read_text())["entries"] for p in (a, b))
    same = differ = 0
    for kind in ra:
        for ea, eb in zip(ra[kind], rb[kind], strict=True):
            if _strip(ea) == _strip(eb):
                same += 1
            else:
                differ += 1
                print("  results differ:", kind, ea["index"], ea["key"])
    print(f"results.json entries (metrics, timings left out): {same} identical, {differ} differ")
    ta, tb = ((p / "table1.md").read_text().splitlines() for p in (a, b))
    lines = [i for i, (x, y) in enumerate(zip(ta, tb, strict=True)) if x != y and "latency" not in x]
    print(f"table1.md: {len(ta)} lines, {len(lines)} differ outside the latency line")
    files = sorted(Path(f"{a}.dump").glob("*.npz"))
    equal = 0
    worst = 0.0
    for fa in files:
        fb = Path(f"{b}.dump") / fa.name
        with np.load(fa, allow_pickle=True) as xa, np.load(fb, allow_pickle=True) as xb:
            ok = sorted(xa.files) == sorted(xb.files)
            for key in xa.files:
                va, vb = xa[key], xb[key]
                if va.shape != vb.shape or va.dtype != vb.dtype or not np.array_equal(va, vb):
                    ok = False
                    if va.shape == vb.shape and va.dtype.kind in "fiub":
                        worst = max(worst, float(np.abs(va.astype(np.float64) - vb.astype(np.float64)).max()))
        equal += ok
    print(f"dumps: {equal} of {len(files)} entries equal array by array (largest difference {worst:g})")


if __name__ == "__main__":
    main()
