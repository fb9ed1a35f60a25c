"""fragments.py DUMP...: per delete / occluder-removed entry of dbench.py dumps (predicted rows), the other proposals
that cover part of the removed car's true pixels (ground-truth instance mask: an oracle, to diagnose): their pixels
on the car, and the share of their own pixels that lie on it (a fragment of the same car: most of it; a neighbour
that spilt onto it: little). Prints one line per such proposal, then the totals by share band."""
import glob
import sys

import numpy as np

bands: dict[str, list[int]] = {}
for dump in sys.argv[1:]:
    for path in sorted(glob.glob(f"{dump}/*.npz")):
        d = np.load(path)
        if str(d["kind"]) not in ("delete", "occluder_removed"):
            continue
        truth = np.isin(d["src_inst"], d["gt_ids"]) & (d["src_inst"] != 0)
        props = d["proposals"]
        for pid in np.unique(props[truth]):
            if pid == 0 or pid in d["picks"]:
                continue
            mine = props == pid
            on, share = int((mine & truth).sum()), float((mine & truth).sum() / mine.sum())
            band = "share >= 0.7" if share >= 0.7 else "0.3-0.7" if share >= 0.3 else "< 0.3"
            bands.setdefault(band, [0, 0])
            bands[band][0] += 1
            bands[band][1] += on
            print(f"{dump.split('/')[-1]} {path[-8:-4]} {d['kind']} proposal {pid}: {on} px on the car, "
                  f"{share:.2f} of its own")
for band, (n, px) in sorted(bands.items()):
    print(f"== {band}: {n} proposals, {px} px of removed cars")
