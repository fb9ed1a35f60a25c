# ruff: noqa: E501, E701, E702
"""fillsplit.py DUMP...: ana.py's class T & fill (3D-SDN's fill where the target shows the edited car) over the rotate
and zoom entries, split by where it lies: inside the picked proposal's mask (inP), off the mask on the source car
(notP&S, ground truth), or elsewhere (notP&~S); mean linearised dB share and pixel share of the region, per weather."""
import glob
import sys

import numpy as np

for d in sys.argv[1:]:
    acc = {}
    for f in sorted(glob.glob(d + "/*.npz")):
        z = np.load(f)
        if str(z["kind"]) not in ("rotate", "zoom") or z["code"].size == 0: continue
        w = str(z["key"]).split(" ")[0].split("/")[1]
        R = z["region"].astype(bool); T = np.isin(z["tgt_inst"], z["gt_ids"])
        P = np.isin(z["proposals"], z["picks"]) & (z["proposals"] != 0); S = np.isin(z["src_inst"], z["gt_ids"])
        t = z["target"].astype(float) / 255; e3 = ((z["sdn"] / 255 - t) ** 2).mean(-1); e2 = ((z["d2"] / 255 - t) ** 2).mean(-1); m2 = e2[R].mean()
        F = (z["code"] == 4) & R & T
        for nm, m in (("inP", F & P), ("notP&S", F & ~P & S), ("notP&~S", F & ~P & ~S)):
            a = acc.setdefault((w, nm), [0.0, 0.0, 0])
            a[0] += -10 / np.log(10) * (e3[m] - e2[m]).sum() / (R.sum() * m2); a[1] += m.sum() / R.sum(); a[2] += 1
    for (w, nm), (s, p, n) in sorted(acc.items()):
        print(f"{d.split('/')[-1]:20s} {w:5s} {nm:8s} {s / n:+.3f} dB  {p / n:.3f} of R  (n {n})")
