"""pics.py OUT.png MAIN_NAME BRANCH_NAME SEED ROW [N]: labelled before/after strips of the removal entries (delete,
occluder removed) of one tree and row of this helper's t1.sh runs whose 2D paste changed most between the codes (by
|PSNR all| difference, largest first; N entries, default 4): per entry the source photo, the target (ground truth),
3D-SDN (identical on both codes), the 2D paste on main and on the branch, and both 2D pastes cropped around the
pixels that changed (24 pixels around them, nearest-neighbour enlarged), each panel titled. Reads dbench.py's npz
dumps (source, target, sdn, d2; 312x96).
Run: /work/main/.venv/bin/python pics.py OUT.png main br 31 semantic 4
"""

from __future__ import annotations

import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = "/tmp/s22data/base2d/t1"
ROW_TITLES = {"semantic": "predicted", "gt": "ground-truth masks (oracle)"}


def psnr_2d(run: str) -> dict[int, tuple[str, str, float]]:
    """``{entry index: (kind, key, 2D PSNR all)}`` of the removal entries of a run."""
    entries = list(json.load(open(f"{run}/results.json"))["entries"].values())[0]
    out = {}
    for e in entries:
        m = (e.get("metrics") or {}).get("photo") or {}
        if e["edit_kind"] in ("delete", "occluder_removed") and "2d" in m:
            out[e["index"]] = (e["edit_kind"], e["key"], m["2d"]["all"]["psnr"])
    return out


def main(out: str, main_name: str, branch_name: str, seed: str, row: str, count: int) -> None:
    a_run, b_run = f"{ROOT}/{main_name}{seed}_{row}", f"{ROOT}/{branch_name}{seed}_{row}"
    a, b = psnr_2d(a_run), psnr_2d(b_run)
    picked = sorted(set(a) & set(b), key=lambda i: -abs(b[i][2] - a[i][2]))[:count]
    titles = ("source photo", "target (ground truth)", "3D-SDN (main = branch)", "2D paste, main 9b7f993",
              "2D paste, branch s22-base2d", "crop: 2D main", "crop: 2D branch")
    fig, axes = plt.subplots(len(picked), len(titles), figsize=(20, 1.9 * len(picked) + 0.4), squeeze=False,
                             gridspec_kw={"width_ratios": [3.25] * 5 + [1.9, 1.9]})
    for r, i in enumerate(picked):
        da, db = np.load(f"{a_run}.dump/{i:04d}.npz"), np.load(f"{b_run}.dump/{i:04d}.npz")
        changed = (da["d2"] != db["d2"]).any(-1)
        ys, xs = np.nonzero(changed) if changed.any() else (np.array([48]), np.array([156]))
        y0, y1 = max(int(ys.min()) - 24, 0), min(int(ys.max()) + 25, changed.shape[0])
        x0, x1 = max(int(xs.min()) - 24, 0), min(int(xs.max()) + 25, changed.shape[1])
        panels = (da["source"], da["target"], da["sdn"], da["d2"], db["d2"], da["d2"][y0:y1, x0:x1],
                  db["d2"][y0:y1, x0:x1])
        for c, (panel, title) in enumerate(zip(panels, titles, strict=True)):
            ax = axes[r, c]
            ax.imshow(panel, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            extra = ""
            if c == 3:
                extra = f" {a[i][2]:.2f} dB"
            elif c == 4:
                extra = f" {b[i][2]:.2f} dB, {int(changed.sum())} px changed"
            ax.set_title(f"{title}{extra}", fontsize=6)
        axes[r, 0].set_ylabel(f"#{i} {a[i][0]}", fontsize=7)
    fig.suptitle(f"t1_{seed}, {ROW_TITLES[row]}: removal entries whose 2D paste changed most (PSNR all)", fontsize=9)
    fig.tight_layout()
    tmp = f"{out}.tmp.png"
    fig.savefig(tmp, dpi=90)
    os.replace(tmp, out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], int(sys.argv[6]) if len(sys.argv) > 6 else 4)
