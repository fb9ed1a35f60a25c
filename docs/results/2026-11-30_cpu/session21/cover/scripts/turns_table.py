"""Branch against main on the counterfactual turn pairs both drew (turns.sh outputs): per tree, source scene and
turn bin, for the car's target pixels and the changed ones (sdn3d-bench's counterfactual.json: the car, the vacated
pixels and the shadow band) and the whole picture (capture_turns.py's .npz), the mean PSNR and L1 of each code, the
paired difference branch - main (10,000-resample bootstrap, 95 %) and wins/losses/ties (PSNR: higher wins; L1: lower
wins); then, per bin, the pixels whose value differs between the two pictures (any channel) and where they lie.

    python turns_table.py LABEL MAIN_OUT BRANCH_OUT [LABEL MAIN_OUT BRANCH_OUT ...]
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict

import numpy as np

from sdn3d.evaluation.paired import paired_difference

SOURCES = {"oracle": "ground-truth geometry (oracle)", "semantic": "predicted"}


def load(out: str) -> tuple[dict, dict]:
    """``({(bin, key): pair json}, {key|angle: (whole psnr, whole l1, picture, masks)})`` of one turns.sh output."""
    pairs = {(p["bin"], p["key"]): p for p in json.load(open(f"{out}/counterfactual.json"))["pairs"]}
    z = np.load(f"{out}.npz")
    whole = {str(k): (float(p), float(l1), pic, m)
             for k, p, l1, pic, m in zip(z["keys"], z["psnr"], z["l1"], z["pictures"], z["masks"], strict=True)}
    return pairs, whole


def source_of(pairs: dict) -> str:
    return SOURCES.get(next(iter(pairs.values()))["source"], "?")


def main() -> int:
    args = sys.argv[1:]
    metric_rows, pixel_rows = [], []
    for i in range(0, len(args), 3):
        label, (mp, mw), (bp, bw) = args[i], load(args[i + 1]), load(args[i + 2])
        source = source_of(mp)
        groups = defaultdict(list)
        for k in sorted(set(mp) & set(bp)):
            if k[0].startswith("turn") and "photo:rays" in mp[k]["metrics"] and "photo:rays" in bp[k]["metrics"]:
                groups[k[0]].append(k)
        for bin_, keys in sorted(groups.items(), key=lambda g: float(g[0].split()[1])):
            angle = bin_.split()[1]
            wkeys = [f"{k[1]}|{float(angle)}" for k in keys]
            wkeys = [w for w in wkeys if w in mw and w in bw]
            for region in ("car", "changed", "whole"):
                for metric, higher in (("psnr", True), ("l1", False)):
                    if region == "whole":
                        a = [bw[w][0 if metric == "psnr" else 1] for w in wkeys]
                        b = [mw[w][0 if metric == "psnr" else 1] for w in wkeys]
                    else:
                        a = [bp[k]["metrics"]["photo:rays"][region][metric] for k in keys]
                        b = [mp[k]["metrics"]["photo:rays"][region][metric] for k in keys]
                    d = paired_difference(a, b, higher)
                    scale = 1.0 if metric == "psnr" else 255.0  # L1 in 0-255 levels
                    metric_rows.append(f"| {label} | {source} | {bin_} | {region} | {metric.upper()} | {d.n} | "
                                       f"{scale * np.mean(b):.3f} | {scale * np.mean(a):.3f} | "
                                       f"{scale * d.mean:+.4f} [{scale * d.low:+.4f}, {scale * d.high:+.4f}] | "
                                       f"{d.wins}/{d.losses}/{d.ties} |")
            differ = np.zeros(4)
            pairs_differing, biggest = 0, 0
            for w in wkeys:
                diff = np.abs(bw[w][2].astype(np.int32) - mw[w][2].astype(np.int32)).max(0)
                where = diff > 0
                masks = mw[w][3]
                car, vacated, shadow = masks & 1 > 0, masks & 2 > 0, masks & 4 > 0
                differ += [(where & car).sum(), (where & vacated & ~car).sum(),
                           (where & shadow & ~vacated & ~car).sum(), (where & ~car & ~vacated & ~shadow).sum()]
                pairs_differing += bool(where.any())
                biggest = max(biggest, int(diff.max()))
            pixel_rows.append(f"| {label} | {source} | {bin_} | {len(wkeys)} | {pairs_differing} | "
                              f"{int(differ.sum())} | {int(differ[0])} | {int(differ[1])} | {int(differ[2])} | "
                              f"{int(differ[3])} | {biggest} |")
    print("| tree | source scene | bin | region | metric | n | main | branch | branch - main [95 %] | "
          "wins/losses/ties |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(metric_rows))
    print()
    print("| tree | source scene | bin | pairs | pairs with a pixel differing | pixels differing (all pairs) | in the "
          "car's target pixels | in the vacated pixels (not the car's) | in the shadow band (only) | elsewhere | "
          "largest difference (0-255) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(pixel_rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
