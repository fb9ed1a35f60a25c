"""pics2.py OUT.png TITLE MAIN_DUMP:BRANCH_DUMP:INDEX[:LABEL] ...: one row per removal entry of two dbench.py runs
(main, branch; npz per entry): the input with the picked proposal's mask outlined (yellow) and the removed car's
true pixels (magenta: the tree's ground-truth instance mask, an oracle shown to diagnose), the target, the 2D paste,
3D-SDN on main, 3D-SDN on the branch (PSNR of the region 'all' in the titles), and the two holes (3D-SDN's pixels the
fill drew: grey inside the proposal, red outside it; on the branch's map, orange: pixels only the branch's hole
took). Cropped around the region, the proposal and both holes (12 pixels more each side), drawn 4x."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from pics import FILL, outline, psnr  # noqa: E402


def main(out: str, title: str, specs: list[str]) -> None:
    fig, axes = plt.subplots(len(specs), 7, figsize=(7 * 2.5, len(specs) * 1.55 + 0.5), squeeze=False)
    for r, spec in enumerate(specs):
        parts = spec.split(":")
        index, label = int(parts[2]), parts[3] if len(parts) > 3 else ""
        a, b = np.load(f"{parts[0]}/{index:04d}.npz"), np.load(f"{parts[1]}/{index:04d}.npz")
        src, tgt, region = a["source"], a["target"], a["region"]
        mask = np.isin(a["proposals"], a["picks"]) & (a["proposals"] != 0)
        truth = np.isin(a["src_inst"], a["gt_ids"]) & (a["src_inst"] != 0)
        inp = src.copy()
        inp[outline(truth)] = (255, 0, 255)
        inp[outline(mask)] = (255, 255, 0)
        ha, hb = a["code"] == FILL, b["code"] == FILL
        maps = []
        for hole, extra in ((ha, None), (hb, hb & ~ha)):
            m = np.full(src.shape, 30, np.uint8)
            m[hole & mask] = 140
            m[hole & ~mask] = (220, 40, 40)
            if extra is not None:
                m[extra] = (255, 170, 0)
            maps.append(m)
        p2, pa, pb = psnr(a["d2"], tgt, region), psnr(a["sdn"], tgt, region), psnr(b["sdn"], tgt, region)
        panels = [(inp, f"{label} #{index} input (yellow proposal, magenta true car: oracle)"), (tgt, "target"),
                  (a["d2"], f"2D paste {p2:.2f} dB"), (a["sdn"], f"3D-SDN main {pa:.2f} dB"),
                  (b["sdn"], f"3D-SDN branch {pb:.2f} dB ({pb - pa:+.2f})"),
                  (maps[0], "main's hole (red: past proposal)"), (maps[1], "branch's hole (orange: added)")]
        ys, xs = np.nonzero(region | mask | ha | hb)
        y0, y1 = max(int(ys.min()) - 12, 0), min(int(ys.max()) + 13, src.shape[0])
        x0, x1 = max(int(xs.min()) - 12, 0), min(int(xs.max()) + 13, src.shape[1])
        for c, (img, name) in enumerate(panels):
            ax = axes[r, c]
            ax.imshow(img[y0:y1, x0:x1], interpolation="nearest")
            ax.set_title(name, fontsize=6.5)
            ax.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=80)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
