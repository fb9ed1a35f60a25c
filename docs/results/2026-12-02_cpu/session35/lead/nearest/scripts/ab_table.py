# ruff: noqa: B007, E401, E402, E501, E701, E702, F401, F541, I001
import collections, statistics, sys
d = collections.defaultdict(dict)
for line in open(sys.argv[1]):
    r, s, v, ms = line.split(); d[(s, v)][int(r)] = int(ms)
for s in ['t1', 't1_180', 't2', 't2_45', 'd1']:
    b, n, o = d[(s, 'base')], d[(s, 'new')], d[(s, 'new_off')]
    rounds = sorted(set(b) & set(n) & set(o))
    ratio = [n[r] / b[r] for r in rounds]
    print(f"{s:7s} base {statistics.median(b.values()):6.0f} new {statistics.median(n.values()):6.0f} off {statistics.median(o.values()):6.0f} | new/base per round {' '.join(f'{x:.2f}' for x in ratio)} median {statistics.median(ratio):.2f} | smoothing's cost base {statistics.median(b[r]-o[r] for r in rounds):.0f} new {statistics.median(n[r]-o[r] for r in rounds):.0f} ms")
