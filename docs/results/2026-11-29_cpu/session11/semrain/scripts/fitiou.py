# ruff: noqa: E501, E701, E702
"""fitiou.py CACHE DUMP: 3D-SDN minus 2D (PSNR all) per modify entry against the picked proposals' fit IoU (the
de-render's meta['fits'], the test-time fit's silhouette IoU with its own mask), binned."""
import glob
import sys

import numpy as np
import torch

scenes = {}
for f in glob.glob(sys.argv[1] + "/*.pt"):
    s = torch.load(f, weights_only=False)
    if s.meta.get("proposals") != "semantic": continue
    w, v, fr = s.meta["source"].split("/")[1:]
    scenes[(w, v, fr)] = {d["id"]: d["fit_iou"] for d in s.meta.get("fits", [])}
rows = []
for f in sorted(glob.glob(sys.argv[2] + "/*.npz")):
    z = np.load(f)
    if str(z["kind"]) not in ("rotate", "zoom", "move"): continue
    key = str(z["key"]); w, v = key.split(" ")[0].split("/"); fr = key.split(" ")[1].split("->")[0]
    fits = scenes.get((w, v, fr), {})
    ious = [fits.get(int(i), np.nan) for i in z["picks"]]
    t = z["target"].astype(float); R = z["region"].astype(bool)
    m3 = ((z["sdn"] - t) ** 2).mean(-1)[R].mean(); m2 = ((z["d2"] - t) ** 2).mean(-1)[R].mean()
    rows.append((np.nanmin(ious) if len(ious) else np.nan, 10 * np.log10(m2 / m3), v, str(z["kind"])))
rows = np.array([(r[0], r[1]) for r in rows]), [r[2:] for r in rows]
a, meta = rows
for lo, hi in ((0, 0.5), (0.5, 0.7), (0.7, 0.8), (0.8, 0.9), (0.9, 1.01)):
    for w in ("clone", "rain"):
        m = (a[:, 0] >= lo) & (a[:, 0] < hi) & np.array([x[0] == w for x in meta])
        if m.any(): print(f"fit IoU [{lo:.1f}, {hi:.1f}) {w:5s}: n={m.sum():3d} 3D-2D mean {a[m, 1].mean():+.2f} wins {int((a[m, 1] > 0).sum())}/{int((a[m, 1] < 0).sum())}")
print("nan fit:", int(np.isnan(a[:, 0]).sum()))
