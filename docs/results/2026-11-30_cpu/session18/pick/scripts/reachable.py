# ruff: noqa: E501
"""reachable.py POSES.json:RUN_DIR [...]: of the operations that pick a proposal at IoU < 0.3 with the true car
(session 13 rotloss's poses.py output; the run's per-entry npz in RUN_DIR.dump), how many had any proposal at
IoU >= 0.3 with that car in the composed source instance map (a rule could have picked it) and how many had none
(no proposal on the car, or only cut pieces). All entries, and the entries 3D-SDN loses to the 2D paste (PSNR all)."""
import json
import sys

import numpy as np


def best_iou(z, gt: int) -> float:
    truth = z["src_inst"] == gt
    best = 0.0
    for p in np.unique(z["proposals"]):
        if p == 0:
            continue
        shown = z["proposals"] == p
        best = max(best, float((shown & truth).sum() / max((shown | truth).sum(), 1)))
    return best


def main(pairs: list[list[str]]) -> None:
    counts = {"all": [0, 0], "losing": [0, 0]}
    for poses, run in pairs:
        for r in json.load(open(poses)):
            z = None
            for k, o in enumerate(r["ops"]):
                if o.get("mask_iou", 1.0) >= 0.3:
                    continue
                z = z if z is not None else np.load(f"{run}.dump/{r['index']:04d}.npz")
                reachable = best_iou(z, int(z["gt_ids"][k])) >= 0.3
                for key in ("all", "losing") if r["d_all"] < 0 else ("all",):
                    counts[key][0 if reachable else 1] += 1
    for key, (yes, no) in counts.items():
        print(f"{key:7s} operations picking at IoU < 0.3: {yes + no}; a proposal at IoU >= 0.3 existed: {yes}; none: {no}")


if __name__ == "__main__":
    main([p.split(":") for p in sys.argv[1:]])
