# ruff: noqa: E501, E701, E702
"""maskcut.py DUMP...: per weather, over the rotate and zoom entries, the picked proposal's mask against its car's
ground-truth visible mask in the source frame (oracle, for scoring): median IoU, bottom row (proposal minus truth;
negative: the mask stops above the car's bottom), share cut by at least 2 px, and the drawn car's bottom row against
the target's (as size.py) for the cut and the uncut masks."""
import glob
import sys

import numpy as np

DRAWN = (1, 2, 3, 5, 7, 8, 11)
for d in sys.argv[1:]:
    out = {}
    for f in sorted(glob.glob(d + "/*.npz")):
        z = np.load(f)
        if str(z["kind"]) not in ("rotate", "zoom") or z["code"].size == 0 or not z["picks"].size: continue
        w = str(z["key"]).split(" ")[0].split("/")[1]
        S = np.isin(z["src_inst"], z["gt_ids"]); P = np.isin(z["proposals"], z["picks"]) & (z["proposals"] != 0)
        T = np.isin(z["tgt_inst"], z["gt_ids"]); D = np.isin(z["code"], DRAWN)
        if S.sum() < 20 or P.sum() < 5 or T.sum() < 20 or D.sum() < 5: continue
        cut = np.nonzero(P.any(1))[0].max() - np.nonzero(S.any(1))[0].max()
        drawn = np.nonzero(D.any(1))[0].max() - np.nonzero(T.any(1))[0].max()
        t = z["target"].astype(float); R = z["region"].astype(bool)
        dp = 10 * np.log10(((z["d2"] - t) ** 2).mean(-1)[R].mean() / ((z["sdn"] - t) ** 2).mean(-1)[R].mean())
        out.setdefault(w, []).append(((S & P).sum() / (S | P).sum(), cut, drawn, dp))
    for w, v in sorted(out.items()):
        v = np.array(v); c = v[:, 1] <= -2
        print(f"{d.split('/')[-1]:20s} {w:5s} n {len(v):3d}: IoU {np.median(v[:, 0]):.2f}, mask bottom - car bottom median {np.median(v[:, 1]):+.1f} px, cut >= 2 px: {int(c.sum())}; "
              f"drawn bottom - target bottom: cut {np.median(v[c, 2]) if c.any() else np.nan:+.1f}, uncut {np.median(v[~c, 2]) if (~c).any() else np.nan:+.1f} px; 3D-2D dB: cut {v[c, 3].mean() if c.any() else np.nan:+.2f}, uncut {v[~c, 3].mean() if (~c).any() else np.nan:+.2f}")
