# ruff: noqa: E501, E701, E702
"""figure.py OUT.png RAW.pt KEY[:CROP] ... : before / after pictures of merged proposals (run from the worktree root with
PYTHONPATH=src:.): per frame (raw.py's key, e.g. vkitti1/0002/clone/00037, optionally :u0,u1 to crop columns), one row
of four titled panels: the frame; main's proposals (stray_distance None); the branch's (GROUPING_DEFAULTS); the
ground-truth Car / Van instances (oracle). Colours are instance ids (the same id, the same colour in main's and the
branch's panels); pixels that left an instance under the branch are drawn black in the branch's panel, with a white
outline of the merged proposal main had."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import torch

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

PALETTE = plt.get_cmap("tab10")


def group(fr, things, stray):
    g = GROUPING_DEFAULTS; prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                          nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                          part_separation=g["part_separation"], stray_distance=stray, stray_reach=g["stray_reach"])[0][0]


def paint(image, inst, ids):
    out = image.astype(float) / 255 * 0.35
    for i in ids:
        m = inst == i
        if m.any(): out[m] = out[m] + 0.65 * np.array(PALETTE(ids.index(i) % 10)[:3])
    return out


out_path, raw_path, *keys = sys.argv[1:]
raw = torch.load(raw_path, weights_only=False); things = raw["things"]
fig, axes = plt.subplots(len(keys), 4, figsize=(18, 2.6 * len(keys) + 0.4), squeeze=False)
for row, spec in zip(axes, keys, strict=True):
    key, _, crop = spec.partition(":")
    fr = raw["frames"][key]
    image = fr["image"].permute(1, 2, 0).numpy()
    a, b = group(fr, things, None).numpy(), group(fr, things, GROUPING_DEFAULTS["stray_distance"]).numpy()  # main, branch
    gi = fr["gt_instances"].numpy(); car = (gi >= INSTANCE_DIVISOR) & np.isin(gi // INSTANCE_DIVISOR, things)
    ids = sorted(set(np.unique(a).tolist()) | set(np.unique(b).tolist()) - {0})
    left = (a > 0) & (b == 0)
    main_img, branch_img = paint(image, a, ids), paint(image, b, ids)
    branch_img[left] = 0.0
    gids = sorted(np.unique(gi[car]).tolist())
    gt_img = paint(image, np.where(car, gi, 0), gids)
    na, nb = len(np.unique(a)) - 1, len(np.unique(b)) - 1
    panels = [(image, f"frame {key} (312x96)"), (main_img, f"main (ea2ed39): {na} proposals"),
              (branch_img, f"branch (stray rule): {nb} proposals; black = {int(left.sum())} px left"),
              (gt_img, "ground-truth Car/Van (oracle)")]
    for ax, (img, title) in zip(row, panels, strict=True):
        ax.imshow(img, interpolation="nearest"); ax.set_title(title, fontsize=9); ax.set_xticks([]); ax.set_yticks([])
    for i in np.unique(a[left]).tolist():
        row[2].contour(a == i, levels=[0.5], colors="white", linewidths=0.8)
    if crop:
        u0, u1 = map(int, crop.split(","))
        for ax in row: ax.set_xlim(u0 - 0.5, u1 - 0.5); ax.set_ylim(95.5, -0.5)
fig.tight_layout(); fig.savefig(out_path, dpi=80)
print(out_path)
