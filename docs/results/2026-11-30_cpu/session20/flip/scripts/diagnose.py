# ruff: noqa: E501, E701, E702
"""diagnose.py LABEL REPLAY.json [...]: replay.py's cars pooled: yaw error figures (flips > 90 degrees, 30-90, median,
90th percentile), and for every car over 30 degrees off, where its end (or axis) was decided wrong:
  search     no fine hypothesis lies within 30 degrees of the truth (the search never reached it);
  silhouette a hypothesis within 30 degrees of the truth was believed more, but its loss was worse by more than the
             fit's facing_tie / tie allowed;
  cue        the appearance believed the wrong hypothesis at least as much as the truth's best one;
  abstain    the truth's hypothesis was believed more, by less than FACING_MARGIN, and lost on loss;
with the winning hypothesis, the lamps' and the bins' parts of the belief at the truth's end, and the loss ratio of the
winner to the truth's best hypothesis."""
import json
import sys
from collections import Counter

import numpy as np

from sdn3d.geometric.fit import FACING_MARGIN

label, files = sys.argv[1], sys.argv[2:]
cars = [c for f in files for c in json.load(open(f))["cars"]]
err = np.array([c["err"] for c in cars])
print(f"== {label}: {len(cars)} cars; flips (>90) {int((err > 90).sum())} ({100 * (err > 90).mean():.1f} %), 30-90 {int(((err > 30) & (err <= 90)).sum())}, "
      f"median {np.median(err):.1f}, p90 {np.percentile(err, 90):.1f}")
kinds = Counter()
for c in sorted(cars, key=lambda c: -c["err"]):
    if c["err"] <= 30: continue
    h = c["hyps"]; win = h[c["winner"]]
    near = [x for x in h if x["err"] <= 30]
    if not near:
        kind = "search"; best = min(h, key=lambda x: x["err"])
    else:
        best = min(near, key=lambda x: x["loss"])
        if best["belief"] <= win["belief"]: kind = "cue"
        elif best["belief"] - win["belief"] < FACING_MARGIN: kind = "abstain"
        else: kind = "silhouette"
    big = "flip" if c["err"] > 90 else "30-90"
    kinds[(big, kind)] += 1
    print(f"  {big:5} {kind:10} err {c['err']:6.1f} hyp {c['hypothesis'][:28]:28} px {c['px']:5d} iou {c['iou']:.2f} lamp {c['lamp']} front {c['front']} "
          f"| win loss {win['loss']:.4f} bel {win['belief']:+.2f} (lamps {win['lamps']:+.2f} net {win['net']:+.2f}) "
          f"| truth-best err {best['err']:5.1f} loss {best['loss']:.4f} bel {best['belief']:+.2f} (lamps {best['lamps']:+.2f} net {best['net']:+.2f}) ratio {win['loss'] / max(best['loss'], 1e-9):.2f} | {c['src']} {c['id']}")
print("  kinds: " + ", ".join(f"{a} {b} {n}" for (a, b), n in sorted(kinds.items())))
