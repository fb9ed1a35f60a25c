# ruff: noqa: E401, E501, E702, I001
"""abt.py AB_FILE: per edit, the medians of base and new and the paired new / base ratio over rounds."""
import sys, statistics as st, collections
d = collections.defaultdict(dict)
for line in open(sys.argv[1]):
    r, s, v, ms = line.split(); d[(s, r)][v] = int(ms)
for s in ('t1', 't1_180', 't2', 't2_45', 'd1'):
    rs = [d[k] for k in d if k[0] == s and len(d[k]) == 2]
    ratio = [x['new'] / x['base'] for x in rs]
    print(f"{s:7s} base median {st.median(x['base'] for x in rs):5.0f} ms  new median {st.median(x['new'] for x in rs):5.0f} ms  paired ratio median {st.median(ratio):.3f} (min {min(ratio):.3f}, max {max(ratio):.3f}, n={len(rs)})")
