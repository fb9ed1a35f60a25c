"""parts.py DUMP [DUMP...]: per removal entry (delete, occluder removed) of Table 1 photo runs (session 11 semrain's
dbench.py dumps), 3D-SDN minus the 2D paste's squared error over the benchmark's 'all' region split by what 3D-SDN did
at each pixel: 'sil' (3D-SDN filled, the 2D paste left the input: the fitted silhouette and shadow past the mask),
'comp' (3D-SDN drew a car there: amodal completion), 'front' (thin things kept in front), 'fill' (both filled: the
fill inside the shared hole), 'only2d' (the 2D paste changed, 3D-SDN kept the input). Each part's dB: the 2D paste's
picture with 3D-SDN's pixels of that part only. Run with /work/main/.venv/bin/python (numpy only)."""
import ast
import sys
from pathlib import Path

import numpy as np

INPUT, FILL, IN_FRONT, RELIT = 0, 4, 10, 9  # sdn3d.editing.photo.settings source codes
PARTS = ("sil", "comp", "front", "fill", "only2d")


def entry(path: Path) -> dict | None:
    d = np.load(path)
    kind = str(d["kind"])
    if kind not in ("dele", "occl", "delete", "occluder_removed"):
        return None
    t, s, b, src = (d[k].astype(np.float64) / 255 for k in ("target", "sdn", "d2", "source"))
    reg = d["region"]
    code = d["code"]
    e3, e2 = ((s - t) ** 2).sum(-1), ((b - t) ** 2).sum(-1)
    changed2 = np.abs(b - src).sum(-1) > 0
    filled3 = (code == FILL) | (code == RELIT)
    drawn3 = (code != INPUT) & ~filled3 & (code != IN_FRONT)
    masks = {"sil": filled3 & ~changed2, "comp": drawn3, "front": code == IN_FRONT, "fill": filled3 & changed2,
             "only2d": (code == INPUT) & changed2}
    n = max(int(reg.sum()) * 3, 1)
    sse2 = max(float(e2[reg].sum()), 1e-9)
    out = {"entry": path.stem, "kind": kind[:4], "n": int(reg.sum()),
           "d": 10 * np.log10(sse2 / max(float(e3[reg].sum()), 1e-9)), "psnr2": 10 * np.log10(n / sse2)}
    for name, m in masks.items():
        dm = float((e3 - e2)[reg & m].sum())
        out[name] = -10 * np.log10(max(sse2 + dm, 1e-9) / sse2)
        out[name + "_px"] = int((reg & m).sum())
        out[name + "_out"] = int((~reg & m).sum())
    pick = np.isin(d["proposals"], d["picks"]) if d["picks"].size else np.zeros_like(reg)
    out["mask_px"] = int(pick.sum())
    out["mask_in_reg"] = int((pick & reg).sum())
    out["picks"] = d["picks"].tolist()
    objs = ast.literal_eval(str(d["objects"])) if str(d["objects"]) else {}
    out["drawn"] = {k: v.get("pixels") for k, v in objs.items()}
    return out


def main(dumps: list[str]) -> None:
    rows = []
    for dump in dumps:
        for p in sorted(Path(dump).glob("*.npz")):
            r = entry(p)
            if r is not None:
                r["run"] = Path(dump).name
                rows.append(r)
    print("run entry kind n(reg) mask(in reg) 3D-2D | dB of each part alone (px in region / px outside)")
    for r in sorted(rows, key=lambda r: r["d"]):
        print(f"{r['run']} {r['entry']} {r['kind']} {r['n']:4d} {r['mask_px']:4d}({r['mask_in_reg']:4d}) "
              f"{r['d']:+7.3f} | " + " ".join(f"{c} {r[c]:+6.2f}({r[c + '_px']}/{r[c + '_out']})" for c in PARTS)
              + f" picks {r['picks']} drawn {r['drawn']}")
    if rows:
        print(f"mean 3D-2D {np.mean([r['d'] for r in rows]):+.3f} over {len(rows)}; mean dB of each part alone: "
              + " ".join(f"{c} {np.mean([r[c] for r in rows]):+.3f}" for c in PARTS))


if __name__ == "__main__":
    main(sys.argv[1:])
