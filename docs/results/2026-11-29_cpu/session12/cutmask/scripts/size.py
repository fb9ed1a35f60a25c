# ruff: noqa: E501, E701, E702
"""size.py DUMP...: per weather, over the rotate and zoom entries of each run's dump (dbench.py), 3D-SDN's drawn car
(its PhotoResult.source codes of drawn pixels) against the target's edited car (ground truth, for scoring): median
area ratio, bottom-row difference (drawn minus target; negative: drawn higher, i.e. farther), height ratio and IoU."""
import glob
import sys

import numpy as np

DRAWN = (1, 2, 3, 5, 7, 8, 11)
for d in sys.argv[1:]:
    out = {}
    for f in sorted(glob.glob(d + "/*.npz")):
        z = np.load(f)
        if str(z["kind"]) not in ("rotate", "zoom") or z["code"].size == 0: continue
        w = str(z["key"]).split(" ")[0].split("/")[1]
        T = np.isin(z["tgt_inst"], z["gt_ids"]); D = np.isin(z["code"], DRAWN)
        if T.sum() < 20 or D.sum() < 5: continue
        rT = np.nonzero(T.any(1))[0]; rD = np.nonzero(D.any(1))[0]
        out.setdefault(w, []).append((D.sum() / T.sum(), rD.max() - rT.max(), (rD.max() - rD.min() + 1) / (rT.max() - rT.min() + 1), (D & T).sum() / (D | T).sum()))
    for w, v in sorted(out.items()):
        v = np.array(v)
        print(f"{d.split('/')[-1]:24s} {w:5s} n {len(v):3d}: median area ratio drawn/target {np.median(v[:, 0]):.2f}, bottom row drawn-target {np.median(v[:, 1]):+.1f} px (mean {v[:, 1].mean():+.2f}), height ratio {np.median(v[:, 2]):.2f}, IoU {np.median(v[:, 3]):.2f}")
