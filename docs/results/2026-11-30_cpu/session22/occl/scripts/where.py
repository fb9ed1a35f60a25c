"""where.py DUMP [DUMP...]: where the occluder-removed entries of Table 1 photo runs (session 11 semrain's dbench.py
dumps) lose or gain against the 2D paste. Per entry, over the benchmark's 'all' region (the deleted occluder's
ground-truth pixels): PSNR of 3D-SDN and of the 2D paste, and the squared-error difference (3D-SDN minus 2D, summed
over the region's pixels, per channel in [0, 1]) split by what the target shows there (the revealed car: a car in the
target; background) and by what 3D-SDN drew there (its PhotoResult.source code: 'fill' or 'car', the amodal
completion of the car behind) and, outside the region, the change of pixels anywhere else. Run with
/work/main/.venv/bin/python (numpy only)."""
import sys
from pathlib import Path

import numpy as np

FILL, INPUT, IN_FRONT = 4, 0, 10  # sdn3d.editing.photo.settings source codes


def entry(path: Path) -> dict | None:
    d = np.load(path)
    if str(d["kind"]) != "occluder_removed":
        return None
    t, s, b = (d[k].astype(np.float64) / 255 for k in ("target", "sdn", "d2"))
    reg = d["region"]
    e3, e2 = ((s - t) ** 2).sum(-1), ((b - t) ** 2).sum(-1)
    code = d["code"]
    car_t = d["tgt_inst"] != 0
    drawn = (code != FILL) & (code != INPUT) & (code != IN_FRONT) if code.shape == reg.shape else np.zeros_like(reg)
    n = max(int(reg.sum()) * 3, 1)
    out = {"entry": path.stem, "n": int(reg.sum()),
           "psnr3": 10 * np.log10(1 / max(e3[reg].sum() / n, 1e-12)),
           "psnr2": 10 * np.log10(1 / max(e2[reg].sum() / n, 1e-12))}
    diff = e3 - e2
    for name, m in (("car_drawn", reg & car_t & drawn), ("car_fill", reg & car_t & ~drawn),
                    ("bg_drawn", reg & ~car_t & drawn), ("bg_fill", reg & ~car_t & ~drawn)):
        out[name] = float(diff[m].sum())
        out[name + "_px"] = int(m.sum())
    # dB each region part alone moves PSNR all: the 2D paste's picture with 3D-SDN's pixels of that part only.
    sse2 = max(float(e2[reg].sum()), 1e-9)
    for name in ("car_drawn", "car_fill", "bg_drawn", "bg_fill"):
        out[name + "_db"] = -10 * np.log10(max(sse2 + out[name], 1e-9) / sse2)
    out["outside"] = float(diff[~reg].sum())
    out["outside_px"] = int(((np.abs(s - b).sum(-1) > 0) & ~reg).sum())
    return out


def main(dumps: list[str]) -> None:
    rows = []
    for dump in dumps:
        for p in sorted(Path(dump).glob("*.npz")):
            r = entry(p)
            if r is not None:
                r["run"] = Path(dump).name
                rows.append(r)
    cols = ("car_drawn", "car_fill", "bg_drawn", "bg_fill", "outside")
    print("run entry n psnr3-psnr2 | dSSE (3D-2D): " + " ".join(f"{c}(px)" for c in cols))
    for r in rows:
        print(f"{r['run']} {r['entry']} {r['n']:4d} {r['psnr3'] - r['psnr2']:+7.3f} | "
              + " ".join(f"{r[c]:+7.2f}({r[c + '_px']})" for c in cols))
    if rows:
        mean = np.mean([r["psnr3"] - r["psnr2"] for r in rows])
        print(f"mean dPSNR {mean:+.3f} over {len(rows)}; dSSE sums: "
              + " ".join(f"{c} {sum(r[c] for r in rows):+.2f}" for c in cols))
        print("mean dB of each part alone (3D-SDN's pixels there, the 2D paste's elsewhere): "
              + " ".join(f"{c} {np.mean([r[c + '_db'] for r in rows]):+.3f}" for c in cols[:4]))


if __name__ == "__main__":
    main(sys.argv[1:])
