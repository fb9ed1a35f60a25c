"""kinds.py ROW PREFIX...: every flip (> 90 degrees; the truth an oracle, for scoring only) of diag.sh's runs sorted
into session 20 flip's kinds: search (no fine hypothesis within 30 degrees of the truth), cue (the belief in the
truth's best hypothesis was not higher than the winner's), abstain (higher by less than FACING_MARGIN), silhouette
(higher by FACING_MARGIN or more, but its loss was worse than facing_tie allows); with the loss ratio winner /
truth's best and both beliefs. Run with main's code on the path (PYTHONPATH=TREE/src:scripts)."""
import math
import sys
from collections import Counter

from score import load

from sdn3d.geometric.fit import FACING_MARGIN


def err(a: float, b: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))


row, prefixes = sys.argv[1], sys.argv[2:]
kinds = Counter()
for c in load(prefixes, row):
    d = c["diag"]
    if c["yaw_deg"] <= 90 or d is None:
        continue
    hyps = [(err(r, c["true_ry"]), loss, b) for r, loss, b in zip(d["hyp_ry"], d["loss"], d["belief"], strict=True)]
    win = hyps[d["winner"]]
    near = [h for h in hyps if h[0] <= 30]
    if not near:
        kind, best = "search", min(hyps)
    else:
        best = min(near, key=lambda h: h[1])
        kind = ("cue" if best[2] <= win[2] else "abstain" if best[2] - win[2] < FACING_MARGIN else "silhouette")
    kinds[kind] += 1
    print(f"  {kind:10} {c['yaw_deg']:6.1f} {c['tree'].rsplit('_', 1)[-1]} {c['frame']} id {c['id']} px "
          f"{c['pixels']} cut {int(c['truncated'])} | win loss {win[1]:.4f} bel {win[2]:+.2f} | truth-best err "
          f"{best[0]:.0f} loss {best[1]:.4f} bel {best[2]:+.2f} ratio {win[1] / max(best[1], 1e-9):.2f}")
print(dict(kinds))
