"""Table 1 (photo mode) per kind of edit: this branch's 3D-SDN row minus main's, paired over the same entries
(sdn3d.evaluation.paired; PSNR / SSIM higher is better, L1 lower).

usage: table1_compare.py MAIN/results.json NEW/results.json [METHOD]
"""

import json
import sys

from sdn3d.evaluation.paired import paired_difference

old, new = (json.load(open(p))["entries"]["oracle"] for p in sys.argv[1:3])
method = sys.argv[3] if len(sys.argv) > 3 else "3d-sdn"
old = {e["key"]: e for e in old}
kinds = sorted({e["edit_kind"] for e in new}) + ["every"]
print("| kind | n | region | ΔPSNR | ΔSSIM | ΔL1 |\n|---|---|---|---|---|---|")
for kind in kinds:
    rows = [(old[e["key"]], e) for e in new if (kind == "every" or e["edit_kind"] == kind) and e["key"] in old]
    for region in ("all", "whole"):
        cells = []
        for metric, hib, digits in (("psnr", True, 2), ("ssim", True, 4), ("l1", False, 4)):
            a = [n["metrics"]["photo"][method][region][metric] for _, n in rows]
            b = [o["metrics"]["photo"][method][region][metric] for o, _ in rows]
            d = paired_difference(a, b, higher_is_better=hib)
            cells.append(
                f"{d.mean:+.{digits}f} [{d.low:+.{digits}f}, {d.high:+.{digits}f}] {d.wins}/{d.losses}/{d.ties}"
            )
        print(f"| {kind} | {len(rows)} | {region} | " + " | ".join(cells) + " |")
