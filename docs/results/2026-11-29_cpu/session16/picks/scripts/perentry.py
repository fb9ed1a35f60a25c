# ruff: noqa: E501, E701, E702
"""perentry.py BASE_RUN NEW_RUN [N]: the entries of two runs of one tree (main's, the branch's) with the largest
|3D-SDN new - base| PSNR all (N, default 15), each with both codes' 3D-SDN picks (dbench.py's npz) and the 2D paste's
change; then the summed new-base over the entries whose 3D-SDN picks changed and over the others."""
import json
import os
import sys

import numpy as np


def load(run):
    r = json.load(open(f"{run}/results.json"))
    return {e["index"]: e for e in list(r["entries"].values())[0]}


b, n = sys.argv[1:3]; top = int(sys.argv[3]) if len(sys.argv) > 3 else 15
a, c = load(b), load(n)
rows = []
for i in sorted(set(a) & set(c)):
    ma, mc = (a[i].get("metrics") or {}).get("photo") or {}, (c[i].get("metrics") or {}).get("photo") or {}
    if "3d-sdn" not in ma or "3d-sdn" not in mc: continue
    pa = np.load(f"{b}.dump/{i:04d}.npz")["picks"].tolist() if os.path.exists(f"{b}.dump/{i:04d}.npz") else []
    pc = np.load(f"{n}.dump/{i:04d}.npz")["picks"].tolist() if os.path.exists(f"{n}.dump/{i:04d}.npz") else []
    rows.append((i, a[i]["key"], a[i]["edit_kind"], mc["3d-sdn"]["all"]["psnr"] - ma["3d-sdn"]["all"]["psnr"],
                 mc["2d"]["all"]["psnr"] - ma["2d"]["all"]["psnr"], pa, pc))
moved = [r for r in rows if r[5] != r[6]]; kept = [r for r in rows if r[5] == r[6]]
print(f"{n} - {b}: 3D-SDN new-base PSNR all: picks changed on {len(moved)} entries, sum {sum(r[3] for r in moved):+.2f} dB "
      f"({sum(r[3] > 1e-9 for r in moved)}/{sum(r[3] < -1e-9 for r in moved)}); picks kept on {len(kept)}, sum {sum(r[3] for r in kept):+.2f} dB "
      f"({sum(r[3] > 1e-9 for r in kept)}/{sum(r[3] < -1e-9 for r in kept)})")
print("  idx key                        kind              3D new-base  2D new-base  3D picks base -> new")
for r in sorted(rows, key=lambda r: -abs(r[3]))[:top]:
    print(f"  {r[0]:3d} {r[1]:26s} {r[2]:16s} {r[3]:+7.2f}     {r[4]:+7.2f}      {r[5]} -> {r[6]}{'  (pick changed)' if r[5] != r[6] else ''}")
