"""colour_cue.py TREE CACHE CUES.json: not a fit cue, a check of the README's "what might work instead": for every
fitted predicted vehicle proposal >= 128 px of CUES.json (fit_cues.py, oracle label), its mask cut in two by
twofit.py's 2-means on (x, y), and the distance between the two halves' median RGB (0-255, the 312x96 frame). One
JSON line per proposal. Session 28 merge40."""
import glob
import json
import sys

import torch
from twofit_cut import two_means

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records

tree, cache, cues = sys.argv[1:4]
records = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}
by_key: dict[str, list[dict]] = {}
for r in json.load(open(cues)):
    if r["area"] >= 128:
        by_key.setdefault(r["key"], []).append(r)
for p in sorted(glob.glob(f"{cache}/*.pt")):
    s = torch.load(p, weights_only=False)
    if s.meta.get("proposals") != "semantic" or s.meta["source"] not in by_key:
        continue
    img = load_frame(records[s.meta["source"]], (312, 96), semantic=False, instances=False).image * 255
    o = s.objects
    for r in by_key[s.meta["source"]]:
        m = o.mask[int((o.instance_id == r["id"]).nonzero()[0])]
        a = two_means(m)
        b = m & ~a
        if int(a.sum()) < 32 or int(b.sum()) < 32:
            continue
        d = float((img[:, a].median(1).values - img[:, b].median(1).values).norm())
        print(json.dumps({"tree": tree.split("_")[-1], "key": r["key"], "id": r["id"], "label": r["label"],
                          "area": r["area"], "rgb_dist": d}))
