# ruff: noqa: E501, E701, E702
"""rotloss.py LABEL TAG RUN:REPLAY.json [...]: how much of the rotate entries' 3D-SDN minus 2D paste (PSNR 'all') of
Table 1 semantic-proposal runs (session 11's dbench.py: results.json and the .dump's picks) goes with flipped or badly
turned fits: each rotate entry's picked objects matched (source frame, instance id) to replay.py's cars of the same
code's captures (the truth an oracle, for scoring only); an entry is 'flipped' if a pick's fit is > 90 degrees off,
'30-90' if one is 30-90 off, 'good' if all picks are within 30, 'unmatched' if a pick has no matched car. Per class:
entries, sum and mean of the gap (3D minus 2D, dB) and the share of the total loss (the sum of the negative gaps)."""
import glob
import json
import os
import sys

import numpy as np

label, tag, pairs = sys.argv[1], sys.argv[2], [p.split(":") for p in sys.argv[3:]]
classes = {}
for run, replay in pairs:
    cars = {(c["src"], c["id"]): c for c in json.load(open(replay))["cars"]}
    entries = {e["index"]: e for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]}
    for f in sorted(glob.glob(f"{run}.dump/*.npz")):
        z = np.load(f, allow_pickle=True)
        if str(z["kind"]) != "rotate": continue
        e = entries[int(os.path.basename(f)[:4])]
        m = e["metrics"].get("photo", {})
        if "3d-sdn" not in m or "2d" not in m: continue
        gap = m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"]
        world, rest = str(z["key"]).split("/"); var, frames = rest.split(" "); src = f"vkitti1/{world}/{var}/{frames.split('->')[0]}"
        errs = [cars[(src, int(p))]["err"] if (src, int(p)) in cars else None for p in z["picks"]]
        kind = "unmatched" if (not errs or None in errs) else "flipped" if max(errs) > 90 else "30-90" if max(errs) > 30 else "good"
        classes.setdefault(kind, []).append(gap)
loss = -sum(g for v in classes.values() for g in v if g < 0)
total = sum(len(v) for v in classes.values())
print(f"== {label} ({tag}): {total} rotate entries; 3D-SDN minus 2D PSNR all; total loss (sum of negative gaps) {loss:.2f} dB")
for k in ("good", "30-90", "flipped", "unmatched"):
    v = np.array(classes.get(k, []))
    if not len(v): continue
    neg = -v[v < 0].sum()
    print(f"  {k:10} {len(v):3d} entries, gap sum {v.sum():+7.2f}, mean {v.mean():+.3f}, wins/losses {int((v > 0).sum())}/{int((v < 0).sum())}, share of the loss {neg / loss:.2f}")
