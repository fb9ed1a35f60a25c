# ruff: noqa: E501, E701, E702
"""picks.py DUMP RAW.pt: the Table 1 entries (one photo run of session 11 semrain's dbench.py: DUMP = its .dump folder
of per-entry npz files) whose operation picks a merged proposal: a proposal that holds two or more ground-truth cars
(|P & c| >= 0.3 |c| and >= 16 px, Car / Van; the ground truth is an oracle used for scoring only). RAW.pt (raw.py's
file of the same tree) gives each car's camera distance, to say whether the picked car is the nearest (the occluder)
or a hidden one. Prints one line per such operation and the counts."""
import glob
import os
import sys

import numpy as np
import torch

from sdn3d.labels import INSTANCE_DIVISOR

dump, rawp = sys.argv[1], sys.argv[2]
raw = torch.load(rawp, weights_only=False); things = raw["things"]
ranges = {"/".join(k.split("/")[1:]): fr["gt_range"] for k, fr in raw["frames"].items()}  # "0001/clone/00032"
n_ops = n_merged = 0; entries = set()
for f in sorted(glob.glob(f"{dump}/*.npz")):
    z = np.load(f); i = int(os.path.basename(f)[:4])
    prop, src = z["proposals"], z["src_inst"]
    key = str(z["key"]); frame = key.split("->")[0]; w, rest = frame.split("/"); var, srcf = rest.split(" ")
    rng = ranges.get(f"{w}/{var}/{srcf}", {})
    cars = {int(c): src == c for c in np.unique(src) if c >= INSTANCE_DIVISOR and c // INSTANCE_DIVISOR in things and (src == c).sum() >= 16}
    for pick, gt in zip(z["picks"].tolist(), z["gt_ids"].tolist(), strict=False):
        n_ops += 1
        if pick <= 0: continue
        P = prop == pick
        held = sorted([c for c, m in cars.items() if (P & m).sum() >= max(16, 0.3 * m.sum())], key=lambda c: rng.get(c % INSTANCE_DIVISOR, 1e9))
        if len(held) < 2: continue
        n_merged += 1; entries.add(i)
        role = "occluder" if gt == held[0] else ("hidden" if gt in held else "neither")
        print(f"entry {i:3d} {key:26s} pick {pick} ({int(P.sum())} px) holds {[(c, int((P & cars[c]).sum()), int(cars[c].sum())) for c in held]}; the edited car {gt} is the {role}")
print(f"{dump}: {n_merged} of {n_ops} operations (in {len(entries)} entries) pick a merged proposal")
