# ruff: noqa: E501
"""layout_by_kind.py SEED...: per tuning tree and row of main's Table 1 photo runs (/tmp/s20data/lead/t1/main<SEED>_<row>),
per kind of edit: entries, mean 3D-SDN minus 2D paste PSNR *all*, 3D-SDN's wins, and the mean layout mask IoU (where each
method draws the edited cars against where the target shows them) of 3D-SDN and of the 2D paste."""
import json
import statistics as st
import sys

T = "/tmp/s20data/lead/t1"
for seed in sys.argv[1:]:
    for row in ("semantic", "gt"):
        entries = list(json.load(open(f"{T}/main{seed}_{row}/results.json"))["entries"].values())[0]
        for kind in ("rotate", "zoom", "delete", "occluder_removed"):
            es = [e for e in entries if e.get("edit_kind") == kind and not e.get("errors")]
            if not es:
                continue
            photo = [e["metrics"]["photo"] for e in es]
            gap = [p["3d-sdn"]["all"]["psnr"] - p["2d"]["all"]["psnr"] for p in photo]
            iou = [(p["3d-sdn"]["layout"]["mask_iou"], p["2d"]["layout"]["mask_iou"]) for p in photo if "layout" in p["3d-sdn"]]
            layout = f"layout3d {st.mean(a for a, _ in iou):.3f} 2d {st.mean(b for _, b in iou):.3f}" if iou else ""
            print(seed, row, kind, len(es), f"dPSNR mean {st.mean(gap):.3f}", "wins", sum(g > 0 for g in gap), layout)
