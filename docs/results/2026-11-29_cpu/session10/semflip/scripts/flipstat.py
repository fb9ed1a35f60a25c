# ruff: noqa: E402, E501, E701, E702
"""flipstat.py DIAG.json...: rotate entries split by whether the turned object (|turn| >= 15 deg) was fitted end for
end (yaw error > 90) and by variation; mean 3D-2D (PSNR all) and the sum of losses."""
import json
import sys

import numpy as np

rows = [r for f in sys.argv[1:] for r in json.load(open(f))]
def cls(r):
    ops = [o for o in r["ops"] if abs(o["turn_deg"]) >= 15]
    flip = any(o.get("flip") for o in ops)
    poor = any((o.get("fit") or {}).get("poor_fit") for o in ops)
    return ("flipped" if flip else "right-way") + ("+poor" if poor else ""), r["key"].split()[0].split("/")[1]
groups = {}
for r in rows: groups.setdefault(cls(r), []).append(r["d_all"])
tot = sum(d for r in rows for d in [r["d_all"]] if d < 0)
print(f"n={len(rows)} mean {np.mean([r['d_all'] for r in rows]):+.2f}; sum of losses {tot:.1f}")
for k in sorted(groups):
    d = np.array(groups[k]); print(f"{k}: n={len(d)} mean {d.mean():+.2f} wins {(d>0).sum()}/{(d<0).sum()} sum of losses {d[d<0].sum():.1f} worst {d.min():+.2f}")
