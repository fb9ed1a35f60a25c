# ruff: noqa: E402, E501, E701, E702
"""What a perfect fog detector would give (the correction only on fog entries, by the tree's own label) against always-on."""
import sys

sys.path.insert(0, "/tmp/s7data/haze")
import numpy as np
import sim

rows = sim.t1_rows() + sim.cf_rows()
groups = {}
for r in rows:
    g = r["on"] if r["weather"] == "fog" else r["off"]
    groups.setdefault((r["set"], r["kind"], r["weather"]), []).append(g - r["on"])
for k in sorted(groups):
    v = np.array(groups[k])
    if np.abs(v).max() > 1e-9: print(k, "fog-only minus always-on:", sim.ci(v))
