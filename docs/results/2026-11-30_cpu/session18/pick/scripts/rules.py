# ruff: noqa: E501
"""rules.py TREE:CACHE [...]: without rendering, how often each picking rule takes the true car, per row (semantic
proposals; ground-truth masks (oracle)) of Table 1 trees at 312x96, on the cached de-rendered source scenes of session
11's dbench.py. The true car of an operation: the ground-truth object its `from` point names (edit_regions, by
projected centre: oracle, for scoring only); a pick's IoU: its proposal's visible pixels (composed instance map)
against the true car's in the source frame. Rules: centre = main's (projected centre, one-to-one); boxcentre = the
paper's (nearest visible-mask box centre, one-to-one here); mask-first = pick_objects without its centre snap (mask
under the point, box, centre); snap N px = with the snap at N px of 312; branch = pick_objects as committed
(CENTRE_SNAP = 1/150 of the width, 2.08 px). Prints per row and rule: operations, picks at IoU < 0.3, >= 0.5, and the mean IoU."""
import glob
import sys

import numpy as np
import torch
from scipy.optimize import linear_sum_assignment

import sdn3d.editing.pick as pick_module
from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation
from sdn3d.data.sources import read_source
from sdn3d.editing.pick import PickBy, pick_objects, projected_centers
from sdn3d.evaluation.edit_benchmark import _instances, edit_regions, index_records
from sdn3d.image_ops import mask_boxes
from sdn3d.scene.maps import compose_instances

SIZE = (312, 96)


def centre_pick(scene, points, need):
    return pick_objects(scene, points, need, by=PickBy.CENTRE)


def boxcentre_pick(scene, points, need):
    boxes = mask_boxes(scene.objects.mask).double()
    mid = torch.stack([(boxes[:, 0] + boxes[:, 2] - 1) / 2, (boxes[:, 1] + boxes[:, 3] - 1) / 2], 1)
    ok = boxes[:, 2] > boxes[:, 0]
    centers, valid = projected_centers(scene)
    mid = torch.where(ok[:, None], mid, centers)
    d = torch.cdist(torch.tensor(points, dtype=torch.float64), mid)
    usable = (~torch.tensor(need)[:, None] | scene.objects.has_geometry[None]) & (ok | valid)[None]
    cost = torch.where(usable, d, torch.full_like(d, 1e12)).numpy()
    r, c = linear_sum_assignment(cost)
    out = [0] * len(points)
    for i, j in zip(r.tolist(), c.tolist(), strict=True):
        out[i] = int(scene.objects.instance_id[j])
    return out


def visible_pick(share):
    """pick_objects with its centre snap set to ``share`` of the width (0: mask first, no snap)."""
    def pick(scene, points, need):
        kept = pick_module.CENTRE_SNAP
        pick_module.CENTRE_SNAP = share
        try:
            return pick_objects(scene, points, need)
        finally:
            pick_module.CENTRE_SNAP = kept
    return pick


RULES = {"centre": centre_pick, "boxcentre": boxcentre_pick, "mask-first": visible_pick(0.0),
         **{f"snap {d:g}px": visible_pick(d / SIZE[0]) for d in (1.0, 2.0, 4.0)},
         "branch": lambda s, p, n: pick_objects(s, p, n)}


def main(pairs):
    stats = {}
    for tree, cache in pairs:
        entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
        records = index_records(read_source(synth_data_source(tree)))
        scenes = {}
        for f in glob.glob(f"{cache}/*.pt"):
            s = torch.load(f, weights_only=False)
            scenes[(s.meta["source"], s.meta["proposals"])] = s
        for entry in entries:
            if entry.is_identity:
                continue
            src = records[(entry.world, entry.variation, entry.source_frame)]
            tgt = records[(entry.world, entry.variation, entry.target_frame)]
            gt_ids = edit_regions(entry, src, tgt, SIZE)[2]
            truth = _instances(src, SIZE)
            ops = [scale_operation(op, (1242, 375), SIZE) for op in entry.operations]
            points, need = [op.from_uv for op in ops], [op.kind == "modify" for op in ops]
            for row in ("semantic", "gt"):
                scene = scenes.get((src.key, row))
                if scene is None:
                    continue
                shown = compose_instances(scene)
                for name, rule in RULES.items():
                    try:
                        picks = rule(scene, points, need)
                    except ValueError:
                        picks = [0] * len(points)
                    for p, g in zip(picks, gt_ids, strict=True):
                        a, b = shown == p, truth == g
                        iou = float((a & b).sum() / max(int((a | b).sum()), 1))
                        stats.setdefault((row, name), []).append(iou)
    for (row, name), v in sorted(stats.items()):
        v = np.asarray(v)
        print(f"{row:9s} {name:11s} ops {len(v):4d}  IoU<0.3 {int((v < 0.3).sum()):4d}  IoU>=0.5 {int((v >= 0.5).sum()):4d}  mean IoU {v.mean():.3f}")


if __name__ == "__main__":
    main([p.split(":") for p in sys.argv[1:]])
