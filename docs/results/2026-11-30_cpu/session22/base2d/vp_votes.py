"""vp_votes.py OUT.md RUN...: why the 2D parts change the 2D paste so little on Table 1 at 312x96. For every removal
entry (delete, occluder removed) of each run (this helper's t1.sh outputs, branch code), from dbench.py's npz dump
(source photo, the source scene's composed instance map ``proposals``, picked ids ``picks``) and the synthetic trees'
camera (``VKITTI_INTRINSICS`` resized to 312x96: principal point = the picture's centre): the baselines' hole
(``vacated_hole``), whether the edges around the removed objects vote a vanishing point (``image_vanishing_point`` as
``removal_vanishing_point`` calls it: none / snapped to the camera's forward one / elsewhere) and the leftover pixels
(``removal_guides``). Run with the branch's code:
cd /work/wt/base2d && PYTHONPATH=src /work/main/.venv/bin/python \
    docs/results/2026-11-30_cpu/session22/base2d/vp_votes.py OUT.md /tmp/s22data/base2d/t1/br31_gt ...
"""

from __future__ import annotations

import json
import os
import sys
from collections import Counter

import numpy as np
import torch

from sdn3d.editing.photo.fill import removal_guides, vacated_hole
from sdn3d.editing.photo.road import FORWARD_SNAP_DEG, PictureLab, image_vanishing_point, vanishing_point
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.image_ops import dilate_square
from sdn3d.math3d.camera import VKITTI_INTRINSICS


def main(out: str, runs: list[str]) -> None:
    settings = PhotoSettings()
    K = VKITTI_INTRINSICS.resized(312, 96).matrix(torch.float64)
    forward = vanishing_point(K, None)
    lines = ["| run | removal entries | edges vote: none | snapped to forward | elsewhere | with leftover pixels |",
             "|---|---|---|---|---|---|"]
    for run in runs:
        entries = list(json.load(open(f"{run}/results.json"))["entries"].values())[0]
        counts: Counter = Counter()
        for e in entries:
            if e["edit_kind"] not in ("delete", "occluder_removed"):
                continue
            d = np.load(f"{run}.dump/{e['index']:04d}.npz")
            image = torch.from_numpy(d["source"]).permute(2, 0, 1).float() / 255
            ids, gone = torch.from_numpy(d["proposals"]), torch.from_numpy(d["picks"])
            keep = (ids != 0) & ~torch.isin(ids, gone)
            hole = vacated_hole(ids, gone, keep, settings)
            guides = removal_guides(image, K, PictureLab(image), hole, ids, gone, keep, settings)
            removed = torch.isin(ids, gone) & (ids != 0)
            counts["n"] += 1
            if bool(removed.any()):  # the vote as removal_vanishing_point casts it
                ys, xs = removed.nonzero(as_tuple=True)
                extent = max(int(ys.max() - ys.min()), int(xs.max() - xs.min()))
                region = dilate_square(removed, max(2 * extent, 20)) & ~dilate_square((ids != 0) | removed, 2)
                found = image_vanishing_point(image, region, K, forward_snap_deg=FORWARD_SNAP_DEG)
                counts["none" if found is None else "forward" if np.allclose(found, forward) else "else"] += 1
            counts["leftovers"] += int(bool(guides.leftovers.any()))
        lines.append(f"| {os.path.basename(run)} | {counts['n']} | {counts['none']} | {counts['forward']} | "
                     f"{counts['else']} | {counts['leftovers']} |")
    text = "\n".join(lines) + "\n"
    tmp = f"{out}.tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, out)
    print(text)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
