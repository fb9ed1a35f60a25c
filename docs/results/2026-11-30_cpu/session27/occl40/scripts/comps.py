"""comps.py DUMP [DUMP...]: every amodal completion on the removal entries (delete, occluder removed) of Table 1 photo
dumps (session 11 semrain's dbench.py): per completed car (an object 3D-SDN drew that did not move) its visible
pixels in the source scene's proposals ('seen'), the pixels drawn ('drawn'), the drawn pixels the benchmark's region
holds, and the dB its drawn pixels alone move PSNR all against the 2D paste (3D-SDN's pixels there, the paste's
elsewhere), with candidate trust figures: drawn/seen, the box height of its seen pixels, its drawn pixels' rows
above/below its seen box. Run with /work/main/.venv/bin/python (numpy only)."""
import ast
import sys
from pathlib import Path

import numpy as np

INPUT, FILL, IN_FRONT, RELIT = 0, 4, 10, 9


def rows_of(path: Path, run: str) -> list[dict]:
    d = np.load(path)
    if str(d["kind"])[:4] not in ("dele", "occl"):
        return []
    objs = ast.literal_eval(str(d["objects"])) if str(d["objects"]) else {}
    grown = {k: v for k, v in objs.items() if not v.get("moved", True) and v.get("pixels", 0) > 0}
    if not grown:
        return []
    t, s, b = (d[k].astype(np.float64) / 255 for k in ("target", "sdn", "d2"))
    reg, code, prop = d["region"], d["code"], d["proposals"]
    drawn = (code != INPUT) & (code != FILL) & (code != RELIT) & (code != IN_FRONT)
    e3, e2 = ((s - t) ** 2).sum(-1), ((b - t) ** 2).sum(-1)
    sse2 = max(float(e2[reg].sum()), 1e-9)
    out = []
    for iid, info in grown.items():
        seen = prop == iid
        # the drawn pixels nearest this object's seen pixels (one grown object per entry in nearly all)
        m = drawn
        if len(grown) > 1:
            ys, xs = np.nonzero(seen)
            if len(ys):
                x0, x1 = xs.min(), xs.max()
                cols = np.zeros_like(m)
                cols[:, max(x0 - 20, 0):x1 + 21] = True
                m = drawn & cols
        dm = float((e3 - e2)[reg & m].sum())
        ys, xs = np.nonzero(seen)
        dys, dxs = np.nonzero(m)
        sh = int(ys.max() - ys.min() + 1) if len(ys) else 0
        sw = int(xs.max() - xs.min() + 1) if len(xs) else 0
        out.append({"run": run, "entry": path.stem, "kind": str(d["kind"])[:4], "iid": iid,
                    "seen": int(seen.sum()), "drawn": int(info["pixels"]), "in_reg": int((reg & m).sum()),
                    "db": -10 * np.log10(max(sse2 + dm, 1e-9) / sse2), "seen_h": sh, "seen_w": sw,
                    "drawn_h": int(dys.max() - dys.min() + 1) if len(dys) else 0,
                    "drawn_w": int(dxs.max() - dxs.min() + 1) if len(dxs) else 0,
                    "photo": info.get("photo", 0), "part": info.get("part", 0), "mirror": info.get("mirror", 0)})
    return out


def main(dumps: list[str]) -> None:
    rows = []
    for dump in dumps:
        for p in sorted(Path(dump).glob("*.npz")):
            rows += rows_of(p, Path(dump).name.replace(".dump", ""))
    print("run entry kind iid seen drawn in_reg dB | drawn/seen seen_hxw drawn_hxw photo part mirror")
    for r in sorted(rows, key=lambda r: r["db"]):
        print(f"{r['run']} {r['entry']} {r['kind']} {r['iid']} {r['seen']:4d} {r['drawn']:4d} {r['in_reg']:4d} "
              f"{r['db']:+6.2f} | {r['drawn'] / max(r['seen'], 1):5.2f} {r['seen_h']}x{r['seen_w']} "
              f"{r['drawn_h']}x{r['drawn_w']} {r['photo']:.2f} {r['part']:.2f} {r['mirror']:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
