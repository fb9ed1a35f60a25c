# ruff: noqa: E501, E701, E702
"""codes.py DUMP [WEATHER] [KIND]: ana.py's linearised dB share of 3D-SDN minus 2D, split by 3D-SDN's source code
(PhotoResult.source) and by whether the target shows the edited car there (T) or not (~T)."""
import glob
import sys

import numpy as np

NAMES = ("input", "photo", "mirror", "fallback", "fill", "recolored", "shadow", "part", "default", "relit", "in front", "another car")
K = 10 / np.log(10)
weather = sys.argv[2] if len(sys.argv) > 2 else "ALL"; kind = sys.argv[3] if len(sys.argv) > 3 else "ALL"
acc = {}; n = 0
for f in sorted(glob.glob(sys.argv[1] + "/*.npz")):
    z = np.load(f)
    w = str(z["key"]).split(" ")[0].split("/")[1]
    if (weather != "ALL" and w != weather) or (kind != "ALL" and str(z["kind"]) != kind) or z["code"].size == 0: continue
    t = z["target"].astype(float) / 255; e3 = ((z["sdn"] / 255 - t) ** 2).mean(-1); e2 = ((z["d2"] / 255 - t) ** 2).mean(-1)
    R = z["region"].astype(bool)
    if not R.any(): continue
    n += 1; mse2 = e2[R].mean(); T = np.isin(z["tgt_inst"], z["gt_ids"])
    for c in range(12):
        for tn, tm in (("T", T), ("~T", ~T)):
            m = R & tm & (z["code"] == c)
            if m.any():
                k = (NAMES[c], tn); s, p = acc.get(k, (0.0, 0.0))
                acc[k] = (s - K * (e3[m] - e2[m]).sum() / (R.sum() * mse2), p + m.sum() / R.sum())
print(f"{sys.argv[1]} {weather} {kind}: n={n}; mean linearised dB share and pixel share of R per (code, target car)")
for k, (s, p) in sorted(acc.items(), key=lambda kv: kv[1][0]):
    print(f"  {k[0]:12s} {k[1]:3s} {s / n:+.3f} dB  {p / n:.3f}")
