"""fits_table.py FITS.json: fits.py's rows summarised per row (predicted, ground-truth masks (oracle)) over the
entries whose revealed car has a scene object with geometry on that row: entries, median fit IoU, median distance
error (m), entries with the distance off by > 5 m, median yaw error (degrees, unfolded), entries turned back to front
(yaw error > 90); and how many entries have no object with geometry for the revealed car (or a smaller share).
Run with /work/main/.venv/bin/python (numpy only)."""
import json
import sys

import numpy as np


def main(path: str) -> None:
    rows = json.load(open(path))
    print("| row | entries with a fitted object | median fit IoU | median distance error (m) | > 5 m off "
          "| median yaw error (deg) | turned back to front (> 90 deg) | no object with geometry |")
    print("|---|---|---|---|---|---|---|---|")
    for key, title, least in (("predicted", "predicted (the proposal holding most of it)", 0.0),
                              ("predicted", "predicted, own proposal (>= 30 % of its seen pixels)", 0.3),
                              ("oracle", "ground-truth masks (oracle)", 0.0)):
        fitted = [r[key] for r in rows if r[key].get("geometry") and "dist_err" in r[key] and r["own_share"] >= least]
        dist = np.array([f["dist_err"] for f in fitted])
        yaw = np.array([f["yaw_err"] for f in fitted])
        iou = np.array([f["fit_iou"] for f in fitted if f["fit_iou"] is not None])
        print(f"| {title} | {len(fitted)} | {np.median(iou):.3f} | {np.median(dist):.2f} | {(dist > 5).sum()} "
              f"| {np.median(yaw):.1f} | {(yaw > 90).sum()} | {len(rows) - len(fitted)} of {len(rows)} |")


if __name__ == "__main__":
    main(sys.argv[1])
