# ruff: noqa: E501
"""Keep a pose table's JSON small for the records: the table's "all" figures per row and, per object, the fields the
paired comparison reads (frame, id, yaw error, template right, border cut, winning hypothesis, visible pixels).

    python docs/results/2026-11-28_cpu/session6/poses/compact.py TABLE.json OUT.json
"""

from __future__ import annotations

import json
import sys

KEEP = ("frame", "id", "yaw_deg", "template_ok", "truncated", "hypothesis", "pixels", "matched", "dist", "scale", "fit_iou")

if __name__ == "__main__":
    table = json.load(open(sys.argv[1]))
    out = {k: table[k] for k in ("geometric", "data_root", "part", "frames", "lamp_cue", "min_pixels", "fit_settings", "crops", "image_size",
                                  "seconds", "machine") if k in table}
    out["table"] = {row: {k: v for k, v in figs.items() if k in ("all", "matched objects only")}
                    for row, figs in table["table"].items()}
    out["objects"] = {row: [{k: (round(r[k], 4) if isinstance(r[k], float) else r[k]) for k in KEEP if k in r}
                            for r in rows] for row, rows in table["objects"].items()}
    json.dump(out, open(sys.argv[2], "w"), separators=(",", ":"))
