# ruff: noqa: INP001, E501
"""abt.py AB_FILE [COLUMN]: per edit, the medians of base and new and the paired new / base ratio over rounds (ab.sh's
or abin.sh's lines: round, edit, base or new, then times); COLUMN: which time, 0 the first (ab.sh: the wall ms,
abin.sh: the CPU ms), 1 the second (ab.sh: the CPU ms, abin.sh: the median wall ms)."""

import collections
import statistics
import sys

column = 3 + (int(sys.argv[2]) if len(sys.argv) > 2 else 0)
rounds: dict[tuple[str, str], dict[str, float]] = collections.defaultdict(dict)
with open(sys.argv[1]) as lines:
    for line in lines:
        fields = line.split()
        if len(fields) > column:  # a run whose time was not printed is left out
            r, edit, variant = fields[:3]
            rounds[(edit, r)][variant] = float(fields[column])
for edit in ("t1", "t1_180", "t2", "t2_45", "d1"):
    pairs = [v for (e, _), v in rounds.items() if e == edit and len(v) == 2]
    if not pairs:
        continue
    ratio = [p["new"] / p["base"] for p in pairs]
    print(f"{edit:7s} base median {statistics.median(p['base'] for p in pairs):5.0f} ms  "
          f"new median {statistics.median(p['new'] for p in pairs):5.0f} ms  "
          f"paired ratio median {statistics.median(ratio):.3f} (min {min(ratio):.3f}, max {max(ratio):.3f}, "
          f"n={len(pairs)})")
