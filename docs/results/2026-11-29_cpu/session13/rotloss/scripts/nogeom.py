# ruff: noqa: E501, E701, E702
"""nogeom.py TREE CACHE RUN [SOURCE]: the entries of one Table 1 run (results.json; cached source scenes of dbench.py)
where an operation's `from` point is nearest (projected centre, as editing.apply.match_objects measures) to an object
without geometry: 3D-SDN's modify may only pick objects with geometry, so its one-to-one assignment moves that
operation, and maybe others, to other cars, while the 2D paste picks the object under the point. Prints each such
entry's 3D-2D PSNR all and their sum and count, against all entries'."""
import glob
import json
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation
from sdn3d.data.sources import read_source
from sdn3d.editing.apply import projected_centers

tree, cache, run = sys.argv[1:4]
source = sys.argv[4] if len(sys.argv) > 4 else "semantic"
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
records = {(r.world, r.variation, int(r.frame)): r for r in read_source(synth_data_source(tree))}
scenes = {}
for f in glob.glob(f"{cache}/*.pt"):
    s = torch.load(f, weights_only=False); scenes[(s.meta["source"], s.meta["proposals"])] = s
res = {e["index"]: e for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]}
flagged, total = [], []
for i, e in enumerate(entries):
    m = (res.get(i, {}).get("metrics") or {}).get("photo") or {}
    if "3d-sdn" not in m or "2d" not in m: continue
    d = m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"]; total.append(d)
    s = scenes[(records[(e.world, e.variation, e.source_frame)].key, source)]
    centres, valid = projected_centers(s)
    hit = False
    for op in e.operations:
        uv = torch.tensor(scale_operation(op, (1242, 375), (312, 96)).from_uv, dtype=torch.float64)
        dist = (centres - uv).norm(dim=1).masked_fill(~valid, float("inf"))
        k = int(dist.argmin())
        if not bool(s.objects.has_geometry[k]): hit = True
    if hit: flagged.append((i, res[i]["key"], res[i]["edit_kind"], d))
print(f"{run}: {len(flagged)} of {len(total)} entries have an operation nearest to an object without geometry; their 3D-2D sum {sum(f[3] for f in flagged):+.2f} dB, mean {sum(f[3] for f in flagged) / max(len(flagged), 1):+.2f} (all entries: mean {sum(total) / len(total):+.3f}, sum of losses {sum(min(t, 0) for t in total):+.2f}; flagged losses {sum(min(f[3], 0) for f in flagged):+.2f})")
for f in flagged: print(f"  {f[0]:3d} {f[1]:26s} {f[2]:16s} {f[3]:+.2f}")
