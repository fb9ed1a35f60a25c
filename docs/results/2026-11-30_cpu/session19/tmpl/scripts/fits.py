# ruff: noqa: E501, E701, E702
"""fits.py LABEL ROW TREE MAIN_CACHE BRANCH_CACHE [TREE MAIN_CACHE BRANCH_CACHE ...]: the proposal fits of two Table 1
arms read from their de-render caches (dbench.py's: the source scenes the benchmark edited), for the row ROW (semantic |
gt): each fitted vehicle (scene.meta['fits']) matched to the ground-truth car of largest mask IoU (>= 0.3; the truth is
an oracle, used only to score). Prints, per arm, the fit's template accuracy beside the majority floor (the share of
the matched cars' most common true template), flips (|yaw error| > 90 deg), median |yaw error|, and the paired
difference branch minus main in template accuracy: mean, 10k-draw bootstrap 95 % interval (seed 0), cars won/lost;
and the confusion of the branch's fit (truth rows)."""
import glob
import math
import sys
from collections import Counter

import numpy as np
import torch

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.meshes.templates import TEMPLATE_NAMES

label, row, rest = sys.argv[1], sys.argv[2], sys.argv[3:]


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def cars(tree, cache, records):
    out = {}
    for f in glob.glob(f"{cache}/*.pt"):
        s = torch.load(f, weights_only=False)
        if s.meta["proposals"] != row: continue
        _, w, var, fr = s.meta["source"].split("/")
        truth = scene_from_frame(records[(w, var, int(fr))], (312, 96)).objects
        o = s.objects
        for rec in s.meta.get("fits") or []:
            if rec.get("fit_iou") is None: continue  # not fitted: the prediction kept
            i = int((o.instance_id == rec["id"]).nonzero()[0, 0])
            P = o.mask[i]
            inter = (P[None] & truth.mask).flatten(1).sum(1).float(); uni = (P[None] | truth.mask).flatten(1).sum(1).float()
            iou = inter / uni.clamp_min(1); t = int(iou.argmax())
            if float(iou[t]) < 0.3 or int(truth.template_id[t]) < 0: continue
            out[s.meta["source"], rec["id"]] = (int(truth.template_id[t]), int(o.template_id[i]),
                                                math.degrees(wrap(float(o.ry[i]) - float(truth.ry[t]))))
    return out


main, branch = {}, {}
for k in range(0, len(rest), 3):
    tree, a, b = rest[k:k + 3]
    records = index_records(read_frames(tree))
    main.update({(tree, *key): v for key, v in cars(tree, a, records).items()})
    branch.update({(tree, *key): v for key, v in cars(tree, b, records).items()})
keys = sorted(set(main) & set(branch))
print(f"== {label}, {row}: {len(keys)} fitted cars in both arms (main {len(main)}, branch {len(branch)})")
truth = np.array([main[k][0] for k in keys])
t0, n0 = Counter(truth.tolist()).most_common(1)[0]
print(f"majority floor ({TEMPLATE_NAMES[t0]}): {n0 / len(keys):.3f}")
acc = {}
for name, arm in (("main", main), ("branch", branch)):
    right = np.array([arm[k][1] == arm[k][0] for k in keys], dtype=float); acc[name] = right
    ye = np.abs([arm[k][2] for k in keys])
    print(f"  {name:>6}: template {right.mean():.3f}, flips {int((ye > 90).sum())} ({(ye > 90).mean():.3f}), median |yaw error| {np.median(ye):.1f}")
d = acc["branch"] - acc["main"]
bt = d[np.random.default_rng(0).integers(0, len(d), (10000, len(d)))].mean(1)
print(f"  template accuracy, branch minus main: {d.mean():+.3f} [{np.percentile(bt, 2.5):+.3f}, {np.percentile(bt, 97.5):+.3f}] {int((d > 0).sum())}/{int((d < 0).sum())}")
pairs = Counter((branch[k][0], branch[k][1]) for k in keys)
print("  branch's confusion, truth \\ fit: " + " ".join(f"{n[:5]:>6}" for n in TEMPLATE_NAMES))
for t, name in enumerate(TEMPLATE_NAMES):
    r = [pairs[t, f] for f in range(len(TEMPLATE_NAMES))]
    if sum(r): print(f"    {name:11s} " + " ".join(f"{v:6d}" for v in r))
