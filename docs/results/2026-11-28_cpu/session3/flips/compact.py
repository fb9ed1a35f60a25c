"""Write a pose table's JSON small enough to keep (issue 40 records): the table and, per object, what the paired
comparison needs, of the fit row only (frame, id, yaw error, template right, pixels, cut by the border, winning
hypothesis).

    python docs/results/2026-11-28_cpu/session3/flips/compact.py IN.json OUT.json
"""

import json
import sys

KEEP = ("frame", "id", "yaw_deg", "template_ok", "true_template", "pixels", "truncated", "hypothesis")

if __name__ == "__main__":
    d = json.load(open(sys.argv[1]))
    d["objects"] = {
        row: [{k: (round(r[k], 2) if isinstance(r[k], float) else r[k]) for k in KEEP if k in r} for r in rows]
        for row, rows in d["objects"].items()
        if row.startswith("fit")
    }
    json.dump(d, open(sys.argv[2], "w"), separators=(",", ":"))
