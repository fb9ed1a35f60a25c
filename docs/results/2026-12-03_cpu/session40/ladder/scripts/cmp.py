# ruff: noqa: INP001, E501
"""cmp.py BASE RUN...: per kind (and ALL), each run's 3D-SDN minus the 2D paste (PSNR all), and the run minus BASE on
3D-SDN's PSNR all, paired by entry, 95 % bootstrap over entries (2000 draws; one generator for all runs, seed 0)."""
import json
import sys

import numpy as np


def load(folder):
    (entries,) = json.load(open(folder + "/results.json"))["entries"].values()
    return {r["index"]: r for r in entries}


def psnr(r, method):
    value = r["metrics"]["photo"][method].get("all", {}).get("psnr")
    return np.nan if value is None else value


base = load(sys.argv[1])
kinds = sorted({r["edit_kind"] for r in base.values()})
rng = np.random.default_rng(0)
for folder in sys.argv[1:]:
    run = load(folder)
    out = [folder.split("/")[-1][:22].ljust(22)]
    for kind in [*kinds, "ALL"]:
        keys = [k for k in run if k in base and (kind == "ALL" or run[k]["edit_kind"] == kind)]
        gain = np.array([psnr(run[k], "3d-sdn") - psnr(run[k], "2d") for k in keys])
        change = np.array([psnr(run[k], "3d-sdn") - psnr(base[k], "3d-sdn") for k in keys])
        boot = change[rng.integers(0, len(change), (2000, len(change)))].mean(1)
        out.append(f"{kind[:8]}({len(keys)}) 3D-2D {np.nanmean(gain):+.2f} vs base {np.nanmean(change):+.2f} "
                   f"[{np.percentile(boot, 2.5):+.2f},{np.percentile(boot, 97.5):+.2f}]")
    print(" | ".join(out))
