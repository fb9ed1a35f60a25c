# ruff: noqa: E501, E701, E702
"""picks.py TREE CACHE RUN [SOURCE]: per Table 1 entry of one run (results.json; the source scenes dbench.py cached),
each operation's pick by 3D-SDN (editing.apply.ops_from_benchmark, as the benchmark calls it: a refusal is printed)
and by the 2D paste (match_objects without the geometry rule, as baselines.py calls it), under the code on
PYTHONPATH (the run's own). Prints the entries where they differ, with 3D-SDN minus 2D PSNR all and which pick is the
edited car (the benchmark's ground-truth pick on the frame's scene; a proposal counts as that car where its mask's
IoU with the car's source mask is >= 0.3, an oracle used only to score), then the totals."""
import glob
import json
import sys

import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation
from sdn3d.data.sources import read_source
from sdn3d.editing.apply import EditError, match_objects, ops_from_benchmark
from sdn3d.evaluation.edit_benchmark import _instances, edit_regions

SIZE = (312, 96)
tree, cache, run = sys.argv[1:4]
source = sys.argv[4] if len(sys.argv) > 4 else "semantic"
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
records = {(r.world, r.variation, int(r.frame)): r for r in read_source(synth_data_source(tree))}
scenes = {}
for f in glob.glob(f"{cache}/*.pt"):
    s = torch.load(f, weights_only=False); scenes[(s.meta["source"], s.meta["proposals"])] = s
res = {e["index"]: e for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]}


def right(scene, iid, car_mask):
    m = scene.objects.mask[scene.objects.index_of(iid)]
    return float((m & car_mask).sum()) / max(float((m | car_mask).sum()), 1.0) >= 0.3


differ, n_ops, n_small, refused, total = [], 0, 0, [], 0
for i, e in enumerate(entries):
    m = (res.get(i, {}).get("metrics") or {}).get("photo") or {}
    rec = records.get((e.world, e.variation, e.source_frame))
    if rec is None or not e.operations: continue
    s = scenes[(rec.key, "gt" if source == "gt" else source)]
    d = m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"] if "3d-sdn" in m and "2d" in m else float("nan")
    total += 1
    points = [scale_operation(op, (1242, 375), SIZE).from_uv for op in e.operations]
    try:
        p3 = [op.instance_id for op in ops_from_benchmark(e, s, (1242, 375), False)]
    except EditError as exc:
        refused.append((i, res[i]["key"], res[i]["edit_kind"], str(exc))); continue
    p2 = match_objects(s, points, None)
    n_ops += len(points)
    px = {int(k): int(v) for k, v in zip(s.objects.instance_id.tolist(), s.objects.mask.flatten(1).sum(1).tolist(), strict=True)}
    n_small += sum(px[p] < s.meta.get("min_pixels", 64) for p in p3)
    if p3 != p2:
        gt_ids = edit_regions(e, rec, records[(e.world, e.variation, e.target_frame)], SIZE)[2]
        src = _instances(rec, SIZE)
        cars = [src == g for g in gt_ids]
        r3 = "".join("Y" if right(s, p, c) else "n" for p, c in zip(p3, cars, strict=True))
        r2 = "".join("Y" if right(s, p, c) else "n" for p, c in zip(p2, cars, strict=True))
        differ.append((i, res[i]["key"], res[i]["edit_kind"], d, p3, p2, [px[p] for p in p3], [px[p] for p in p2], r3, r2))
print(f"{run}: {len(differ)} of {total} entries pick differently (3D-SDN vs 2D paste); their 3D-2D PSNR all sum {sum(x[3] for x in differ):+.2f} dB; {len(refused)} entries refused by 3D-SDN's pick; {n_small} of {n_ops} 3D-SDN picks are masks under min_pixels")
print("  idx key                        kind              3D-2D  3D picks (px) / 2D picks (px)  right car 3D/2D")
for x in differ:
    print(f"  {x[0]:3d} {x[1]:26s} {x[2]:16s} {x[3]:+6.2f}  {x[4]} ({x[6]}) / {x[5]} ({x[7]})  {x[8]}/{x[9]}")
for x in refused:
    print(f"  refused {x[0]:3d} {x[1]:26s} {x[2]:16s} {x[3]}")
