"""explore.py MAIN_FOLDER: the exploration behind this folder's change, on the occluder-removed entries of the Table 1
tuning runs in MAIN_FOLDER (session 11 semrain's dbench.py dumps main<seed>_<row>.dump, seeds 31 35 37, rows semantic
= predicted and gt = ground-truth masks, an oracle), per row:

1. by source code: the dB each code's pixels alone move 3D-SDN's PSNR all against the 2D paste (3D-SDN's pixels with
   that PhotoResult.source code, the 2D paste's elsewhere), averaged over the entries (fill 4, mirror 2, part 7);
2. per entry that drew a completion (codes other than input, fill, in front): its pixels in the 'all' region, how many
   fall on a car of the target, the dB the drawn pixels alone move PSNR all, and per completed object its pixels, its
   visible pixels and the share of its visible pixels' colour variance its fitted part labels explain (R2: a pose whose
   parts match the photo explains more), the candidate gates that were looked at and not taken;
3. the gates, simulated with the 2D paste's fill standing in for the fill: no completion, and the completion less its
   pixels that border the fill (its outline trimmed by a pixel).

Run with /work/main/.venv/bin/python (numpy only)."""
import ast
import sys
from pathlib import Path

import numpy as np

INPUT, FILL, IN_FRONT = 0, 4, 10  # sdn3d.editing.photo.settings source codes
SEEDS = (31, 35, 37)


def psnr(x: np.ndarray, t: np.ndarray, reg: np.ndarray) -> float:
    return float(10 * np.log10(1 / max(((x - t) ** 2).sum(-1)[reg].sum() / (reg.sum() * 3), 1e-12)))


def r2(src: np.ndarray, parts: np.ndarray, m: np.ndarray) -> float | None:
    if m.sum() < 5:
        return None
    x, lab = src[m], parts[m]
    total = ((x - x.mean(0)) ** 2).sum()
    within = sum(((x[lab == q] - x[lab == q].mean(0)) ** 2).sum() for q in np.unique(lab))
    return float(1 - within / max(total, 1e-9))


def main(folder: str) -> None:
    for row in ("semantic", "gt"):
        by_code: dict[int, float] = {}
        n = 0
        gates = {"main": [], "no completion": [], "trimmed by a pixel": []}
        lines = []
        for seed in SEEDS:
            for p in sorted(Path(folder, f"main{seed}_{row}.dump").glob("*.npz")):
                d = np.load(p)
                if str(d["kind"]) != "occluder_removed":
                    continue
                n += 1
                t, s, b, src = (d[k].astype(np.float64) / 255 for k in ("target", "sdn", "d2", "source"))
                reg, code = d["region"], d["code"]
                e3, e2 = ((s - t) ** 2).sum(-1), ((b - t) ** 2).sum(-1)
                sse2 = e2[reg].sum()
                for c in np.unique(code[reg]):
                    m = reg & (code == c)
                    by_code[int(c)] = by_code.get(int(c), 0.0) - 10 * np.log10((sse2 + (e3 - e2)[m].sum()) / sse2)
                drawn = (code != INPUT) & (code != FILL) & (code != IN_FRONT)
                edge = np.zeros_like(drawn)
                for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
                    edge |= drawn & np.roll(np.roll(code == FILL, dy, 0), dx, 1)
                base = psnr(b, t, reg)
                gates["main"].append(psnr(s, t, reg) - base)
                gates["no completion"].append(psnr(np.where(drawn[..., None], b, s), t, reg) - base)
                gates["trimmed by a pixel"].append(psnr(np.where(edge[..., None], b, s), t, reg) - base)
                if not (drawn & reg).any():
                    continue
                db = -10 * np.log10((sse2 + (e3 - e2)[drawn & reg].sum()) / sse2)
                on_car = int((drawn & reg & (d["tgt_inst"] != 0)).sum())
                objs = ast.literal_eval(str(d["objects"]))
                per = " ".join(
                    f"{k}: {v['pixels']} px, seen {int((d['proposals'] == k).sum())}, R2 "
                    + (f"{q:.2f}" if (q := r2(src, d["parts"], (d["proposals"] == k) & (code == INPUT)
                                               & (d["parts"] >= 0))) is not None else "-")
                    for k, v in objs.items())
                lines.append(f"  {seed} e{p.stem}: drawn {int((drawn & reg).sum())} px in 'all', {on_car} on the "
                             f"target's car, {db:+.3f} dB | {per}")
        label = "predicted" if row == "semantic" else "ground-truth masks (oracle)"
        print(f"== {label}: {n} occluder-removed entries")
        print("by source code (mean dB of its pixels alone): "
              + ", ".join(f"code {c} {v / n:+.3f}" for c, v in sorted(by_code.items())))
        print("gates (3D-SDN minus 2D, PSNR all, mean; the 2D paste's fill standing in): "
              + ", ".join(f"{k} {np.mean(v):+.3f}" for k, v in gates.items()))
        print("\n".join(lines))


if __name__ == "__main__":
    main(sys.argv[1])
