"""abt.py AB_FILE: per edit, the medians of base and new and the paired new / base ratio over rounds (ab.sh's lines:
round, edit, base or new, ms)."""

import collections
import statistics
import sys

rounds: dict[tuple[str, str], dict[str, int]] = collections.defaultdict(dict)
with open(sys.argv[1]) as lines:
    for line in lines:
        fields = line.split()
        if len(fields) == 4:  # a run whose time was not printed is left out
            r, edit, variant, ms = fields
            rounds[(edit, r)][variant] = int(ms)
for edit in ("t1", "t1_180", "t2", "t2_45", "d1"):
    pairs = [v for (e, _), v in rounds.items() if e == edit and len(v) == 2]
    if not pairs:
        continue
    ratio = [p["new"] / p["base"] for p in pairs]
    print(f"{edit:7s} base median {statistics.median(p['base'] for p in pairs):5.0f} ms  "
          f"new median {statistics.median(p['new'] for p in pairs):5.0f} ms  "
          f"paired ratio median {statistics.median(ratio):.3f} (min {min(ratio):.3f}, max {max(ratio):.3f}, "
          f"n={len(pairs)})")
