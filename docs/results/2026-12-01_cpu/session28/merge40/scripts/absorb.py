"""absorb.py TREE CACHE CUES.json: for every merged proposal of CUES.json (fit_cues.py; the ground truth is an
ORACLE, only to label), the share of each held true car's pixels inside the proposal that the fitted car's silhouette
covers (the first car = the one with most pixels in the proposal), one JSON line per merge. Session 28 merge40."""
import glob
import json
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.scene_gt import ground_truth
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.proposal_fit import fitted_silhouettes

tree, cache, cues = sys.argv[1:4]
records = {r.key: r for r in index_records(read_source(synth_data_source(tree))).values()}
mer: dict[str, list[dict]] = {}
for r in json.load(open(cues)):
    if r["label"] == "merge":
        mer.setdefault(r["key"], []).append(r)
for p in sorted(glob.glob(f"{cache}/*.pt")):
    s = torch.load(p, weights_only=False)
    if s.meta.get("proposals") != "semantic" or s.meta["source"] not in mer:
        continue
    o = s.objects
    gi = ground_truth(records[s.meta["source"]], (s.intrinsics.width, s.intrinsics.height)).instances
    for r in mer[s.meta["source"]]:
        k = int((o.instance_id == r["id"]).nonzero()[0])
        m = o.mask[k]
        S = fitted_silhouettes(s.intrinsics, (o.template_id, o.dims, o.ry, o.location, o.phi), torch.tensor([k]))[0]
        parts = sorted(((int((m & (gi == g)).sum()), g) for g in r["held"]), reverse=True)
        cov = [float((m & (gi == g) & S).sum()) / max(px, 1) for px, g in parts]
        print(json.dumps({"tree": tree.split("_")[-1], "key": r["key"], "id": r["id"], "px": [px for px, _ in parts],
                          "covered": cov}))
