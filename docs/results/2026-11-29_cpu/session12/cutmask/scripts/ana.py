# ruff: noqa: E501, E701, E702
"""ana.py DUMP_DIR [WEATHER] [KIND]: where 3D-SDN's loss to the 2D paste lies, per pixel, over the dumped entries
(dbench.py) of one run. Inside the 'all' region, pixels are split by what 3D-SDN put there (its PhotoResult.source
code: drawn car / fill / input) and by whether the target shows the edited car there (ground truth, for scoring).
Each class's share of the PSNR difference is linearised: -10/ln10 * sum(err3 - err2) / (|R| mse2), so the classes
add up to about the entry's PSNR all difference; entries are averaged. Also the proposal's IoU with its car."""
import glob
import sys

import numpy as np

INPUT, PHOTO, MIRROR, FALLBACK, FILL, RECOLORED, SHADOW, PART, DEFAULT, RELIT, IN_FRONT, ANOTHER_CAR = range(12)
DRAWN = (PHOTO, MIRROR, FALLBACK, RECOLORED, PART, DEFAULT, ANOTHER_CAR)
K = 10 / np.log(10)
files = sorted(glob.glob(sys.argv[1] + "/*.npz"))
weather = sys.argv[2] if len(sys.argv) > 2 else "ALL"
kind = sys.argv[3] if len(sys.argv) > 3 else "ALL"
rows = []
for f in files:
    z = np.load(f)
    w = str(z["key"]).split(" ")[0].split("/")[1]
    if weather != "ALL" and w != weather: continue
    if kind != "ALL" and str(z["kind"]) != kind: continue
    tgt = z["target"].astype(float) / 255; e3 = ((z["sdn"] / 255 - tgt) ** 2).mean(-1); e2 = ((z["d2"] / 255 - tgt) ** 2).mean(-1)
    R = z["region"].astype(bool)
    if z["code"].size == 0 or R.sum() == 0: continue
    code = z["code"]
    drawn = np.isin(code, DRAWN); fill = code == FILL; inp = ~drawn & ~fill
    T = np.isin(z["tgt_inst"], z["gt_ids"]); S = np.isin(z["src_inst"], z["gt_ids"])
    P = np.isin(z["proposals"], z["picks"]) & (z["proposals"] != 0) if z["picks"].size else np.zeros_like(S)
    mse3, mse2 = e3[R].mean(), e2[R].mean()
    d = {"f": f.split("/")[-1], "key": str(z["key"]), "kind": str(z["kind"]), "dpsnr": 10 * np.log10(mse2 / mse3),
         "iou": (S & P).sum() / max((S | P).sum(), 1)}
    for name, m in (("T&drawn", T & drawn), ("~T&drawn", ~T & drawn), ("T&fill", T & fill), ("~T&fill", ~T & fill),
                    ("T&input", T & inp), ("~T&input", ~T & inp)):
        mm = m & R
        d[name] = -K * (e3[mm] - e2[mm]).sum() / (R.sum() * mse2)
        d[name + "_px"] = mm.sum() / R.sum()
    rows.append(d)
names = ["T&drawn", "~T&drawn", "T&fill", "~T&fill", "T&input", "~T&input"]
print(f"{sys.argv[1]} {weather} {kind}: n={len(rows)}, mean dPSNR(3D-2D) {np.mean([r['dpsnr'] for r in rows]):+.3f}, linearised sum {np.mean([sum(r[n] for n in names) for r in rows]):+.3f}, mean proposal IoU {np.mean([r['iou'] for r in rows]):.2f}")
print("class        dB share   pixel share of R")
for n in names:
    print(f"{n:10s} {np.mean([r[n] for r in rows]):+8.3f}   {np.mean([r[n + '_px'] for r in rows]):.3f}")
print("worst entries:")
for r in sorted(rows, key=lambda r: r["dpsnr"])[:12]:
    print(f"  {r['f']} {r['key']:32s} {r['kind']:8s} d={r['dpsnr']:+.2f} iou={r['iou']:.2f} " + " ".join(f"{n}={r[n]:+.2f}" for n in names))
