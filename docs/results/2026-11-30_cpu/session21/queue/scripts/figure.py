# ruff: noqa: E501, E701, E702
"""figure.py OUT.png RAW.pt KEY:Q:u0,u1,v0,v1 ... : why a queue pair stays one proposal (run from the worktree root with
PYTHONPATH=src on session 21 hidden's raw.py files). Per frame (raw.py's key; Q: the id of the nearest-centre instance
the split sees, i.e. the grouping without split and part rule; the window u0..u1, v0..v1 shown), one row of five
titled panels: the frame; main's proposals (GROUPING_DEFAULTS; the branch's grouping is main's, unchanged);
the nearest-centre instance the split sees, coloured by the side of its 2-means cut (orange: the smaller side, the
cut's cluster; blue: the rest), with its statistic; the same instance's votes (pixel + offset) drawn as dots coloured by
the ground-truth car each pixel lies on (oracle; grey: on no car); the ground-truth Car / Van instances (oracle)."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

PALETTE = plt.get_cmap("tab10")


def group(fr, things, split, part):
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=G["thing_odds"],
                          threshold=G["center_threshold"], nms_kernel=G["nms_kernel"], top_k=G["top_k"], min_area=G["min_area"],
                          split_separation=split, part_separation=part)[0][0]


def paint(img, ids):
    out = img.copy() * 0.45
    for j, i in enumerate(sorted(x for x in np.unique(ids) if x > 0)):
        out[ids == i] = np.array(PALETTE(j % 10)[:3]) * 255
    return out.astype(np.uint8)


out, path, specs = sys.argv[1], sys.argv[2], sys.argv[3:]
raw = torch.load(path, weights_only=False); things = raw["things"]
fig, axes = plt.subplots(len(specs), 5, figsize=(20, 3.2 * len(specs)), squeeze=False)
for row, spec in zip(axes, specs, strict=True):
    key, qid, cols = spec.split(":"); u0, u1, v0, v1 = (int(x) for x in cols.split(","))
    fr = raw["frames"][key]; img = fr["image"].permute(1, 2, 0).numpy().astype(float)
    inst = group(fr, things, G["split_separation"], G["part_separation"]); pre = group(fr, things, None, None)
    gi = fr["gt_instances"]; h, w = gi.shape
    vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
    vote = torch.stack([uu + fr["offset"][0], vv + fr["offset"][1]], -1)
    q = int(qid); Q = pre == q
    v = vote[Q]; d = v - v.mean(0); cov = d.T @ d / len(d)
    ang = 0.5 * torch.atan2(2 * cov[0, 1], cov[0, 0] - cov[1, 1]); s = d[:, 0] * ang.cos() + d[:, 1] * ang.sin()
    cut = torch.tensor(0.0)
    for _ in range(16):
        hi = s > cut; cut = (s[hi].mean() + s[~hi].mean()) / 2
    hi = s > cut
    r = torch.where(hi, s - s[hi].mean(), s - s[~hi].mean())
    stat = float((s[hi].mean() - s[~hi].mean()) / (((r[hi] ** 2).mean() + (r[~hi] ** 2).mean()) / 2).sqrt().clamp_min(0.5))
    small = hi if hi.sum() <= (~hi).sum() else ~hi
    side = np.zeros((h, w, 3)) + img * 0.45; qm = Q.numpy()
    colors = np.where(small.numpy()[:, None], np.array([255, 140, 0]), np.array([60, 120, 255]))
    side[qm] = colors
    ext = (u0 - 0.5, u1 - 0.5, v1 - 0.5, v0 - 0.5)
    row[0].imshow(img.astype(np.uint8)[v0:v1, u0:u1], extent=ext); row[0].set_title(f"frame {key[8:]} (312x96; u {u0}-{u1}, v {v0}-{v1})", fontsize=9)
    row[1].imshow(paint(img, inst.numpy())[v0:v1, u0:u1], extent=ext); row[1].set_title("main's proposals (= branch: grouping unchanged)", fontsize=9)
    row[2].imshow(side.astype(np.uint8)[v0:v1, u0:u1], extent=ext)
    row[2].set_title(f"split's 2-means on instance {q}: stat {stat:.1f}\norange = cut-off cluster ({int(small.sum())} px), blue = rest", fontsize=9)
    row[3].imshow((img * 0.3).astype(np.uint8)[v0:v1, u0:u1], extent=ext)
    g = gi[Q]; vq = v.numpy()
    order = sorted(x for x in np.unique(gi.numpy()) if x > 0)  # paint()'s colour order: the ground-truth panel's colours
    for c in sorted(x for x in g.unique().tolist() if x > 0):
        m = (g == c).numpy(); row[3].scatter(vq[m, 0], vq[m, 1], s=4, color=PALETTE(order.index(c) % 10), label=f"car {c}")
    m = (g == 0).numpy(); row[3].scatter(vq[m, 0], vq[m, 1], s=4, color="0.7", label="no car")
    row[3].set_xlim(u0 - 0.5, u1 - 0.5); row[3].set_ylim(v1 - 0.5, v0 - 0.5); row[3].legend(fontsize=6, loc="lower left")
    row[3].set_title("its votes (pixel + offset), coloured as the ground-truth car\nthe pixel lies on (oracle)", fontsize=9)
    row[4].imshow(paint(img, gi.numpy())[v0:v1, u0:u1], extent=ext); row[4].set_title("ground-truth Car / Van (oracle)", fontsize=9)
    for a in row: a.set_xticks([]); a.set_yticks([])
fig.tight_layout(); fig.savefig(out, dpi=70); print(out)
