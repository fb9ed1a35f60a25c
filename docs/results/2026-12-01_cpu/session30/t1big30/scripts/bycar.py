# ruff: noqa: E501
"""bycar.py OUT.md: a sensitivity check of tables.py's intervals. The bench's groups (same_edit_groups) join only
entries that are one edit twice; entries that edit the same true car from another source frame (frames 32-39 of a
sequence) or in the other variation (clone / rain share a world's cars) are not independent either. Here the
paired bootstrap (paired_difference, 4000 resamples, seed 0) resamples whole cars: group = (tree, world, variation, the
edited true instance ids: the dump's gt_ids, oracle, used only to group: a car in one variation), and stricter,
(tree, world, ids): a car in both variations (clone and rain render the same cars). Session 30 t1big30. PYTHONPATH=<plain tree>/src."""
import json
import math
import sys

import numpy as np

from sdn3d.evaluation.paired import LOWER_IS_BETTER, paired_difference

T1 = "/tmp/s30/t1big30/t1"
rows = [json.loads(line) for line in open(sys.argv[1].rsplit("/", 1)[0] + "/per_entry.jsonl")]
cars = {}
for e in rows:
    z = np.load(f"{T1}/{e['seed']}_{e['row']}.dump/{e['index']:04d}.npz", allow_pickle=True)
    ids = tuple(sorted(int(i) for i in z["gt_ids"]))
    cars[(e["seed"], e["row"], e["index"])] = ((e["seed"], e["key"].split(" ")[0], ids), (e["seed"], e["key"].split("/")[0], ids))
lines = ["| row | kind | column | n | edits (bench groups) | cars in a variation | cars | 3D-SDN - 2D | "
         "interval, bench groups | interval, car in a variation | verdict | interval, car | verdict |",
         "|" + "---|" * 13]
for row in ("semantic", "gt"):
    for kind in ("rotate", "zoom", "delete", "occluder_removed", "all kinds"):
        for col in ("psnr/all", "l1/all", "psnr/objects", "l1/objects"):
            sel = [e for e in rows if e["row"] == row and (kind == "all kinds" or e["kind"] == kind)
                   and all(math.isfinite(e["values"][m][col]) for m in ("3d-sdn", "2d"))]
            if not sel:
                continue
            a = [e["values"]["3d-sdn"][col] for e in sel]
            b = [e["values"]["2d"][col] for e in sel]
            hib = col.split("/")[0] not in LOWER_IS_BETTER
            d1 = paired_difference(a, b, hib, groups=[e["group"] for e in sel])
            d2 = paired_difference(a, b, hib, groups=[cars[(e["seed"], e["row"], e["index"])][0] for e in sel])
            d3 = paired_difference(a, b, hib, groups=[cars[(e["seed"], e["row"], e["index"])][1] for e in sel])
            f = "{:+.3f}" if hib else "{:+.4f}"
            lines.append(f"| {row} | {kind} | {col} | {d1.n} | {d1.groups} | {d2.groups} | {d3.groups} | {f.format(d1.mean)} | "
                         f"[{f.format(d1.low)}, {f.format(d1.high)}] | [{f.format(d2.low)}, {f.format(d2.high)}] | "
                         f"{d2.verdict} | [{f.format(d3.low)}, {f.format(d3.high)}] | {d3.verdict} |")
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
