# ruff: noqa: E501, E701, E702, E731, B007, B023, B905
"""figure.py OUT.png N RAW.pt...: the N frames (of raw.py's files) whose cars' best proposal IoU changes most between
main's grouping and the branch's (census.py's per-car rows, summed), one row each: the photo; main's proposals; the
branch's; the ground truth's Car/Van instances (an oracle, for scoring only). Proposals are blended over the photo
(each id its colour); every panel titled with the frame and the per-car best IoUs."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import torch
from census import cars, segment
from scipy import ndimage

from sdn3d.semantic.predict import GROUPING_DEFAULTS

ARMS = {"main": {**GROUPING_DEFAULTS, "thing_odds": None, "split_separation": None}, "branch": dict(GROUPING_DEFAULTS)}
out, n = sys.argv[1], int(sys.argv[2])
cands, trees = [], []
for path in sys.argv[3:]:
    raw = torch.load(path, weights_only=False); tree = raw["tree"].rstrip("/").rsplit("/", 1)[-1]; trees.append(tree)
    for key, fr in raw["frames"].items():
        insts = {a: segment(fr, raw["things"], g)[0] for a, g in ARMS.items()}
        ious = {}
        for a, inst in insts.items():
            row = []
            for cid, m in cars(fr, raw["things"], raw["size"]):
                best = 0.0
                for p in inst[m].unique().tolist():
                    if p: best = max(best, float((m & (inst == p)).sum()) / float((m | (inst == p)).sum()))
                row.append(best)
            ious[a] = row
        gain = sum(b - m for b, m in zip(ious["branch"], ious["main"]))
        cands.append((gain, f"{tree} {key.split('/', 1)[-1]}", fr, insts, ious, raw["things"]))
cands.sort(key=lambda c: -c[0])
pick = cands[:n - 1] + [min(cands, key=lambda c: c[0])]  # the largest gains and the largest loss


def blend(img, inst):
    from sdn3d.visualize import colorize_instances
    col = colorize_instances(inst[None])[0].permute(1, 2, 0).numpy()
    m = (inst > 0).numpy()[..., None]
    edge = (ndimage.morphological_gradient(inst.numpy(), size=(3, 3)) > 0)[..., None] & m
    shown = img * (1 - 0.55 * m) + col * 0.55 * m
    return shown * (1 - edge) + edge * 1.0


fig, axes = plt.subplots(len(pick), 4, figsize=(20, 1.9 * len(pick) + 0.4))
for r, (gain, key, fr, insts, ious, things) in enumerate(pick):
    img = fr["image"].permute(1, 2, 0).float().numpy() / 255
    gi = fr["gt_instances"]; car = torch.isin(torch.div(gi, 1000, rounding_mode="floor"), torch.tensor(things)) & (gi > 0)
    panels = [(f"photo, tree {key}", img),
              (f"main's proposals: {(insts['main'].unique() > 0).sum()} ; car IoUs " + " ".join(f"{x:.2f}" for x in ious["main"]), blend(img, insts["main"])),
              (f"branch's proposals: {(insts['branch'].unique() > 0).sum()} ; car IoUs " + " ".join(f"{x:.2f}" for x in ious["branch"]), blend(img, insts["branch"])),
              ("ground-truth Car/Van instances (oracle)", blend(img, torch.where(car, gi, torch.zeros_like(gi))))]
    for c, (title, im) in enumerate(panels):
        ax = axes[r, c]; ax.imshow(im.clip(0, 1), interpolation="nearest"); ax.set_title(title, fontsize=8); ax.axis("off")
fig.suptitle("Semantic branch's instance proposals at 312x96 (session 11's demo weights), trees " + ", ".join(trees) + ": main's grouping against the branch's "
             "(thing_odds 0.6, split_separation 4). Rows: the frames with the largest summed IoU gain, last row the largest loss.", fontsize=9)
fig.tight_layout(); fig.savefig(out, dpi=110)
print(out, [(round(c[0], 2), c[1]) for c in pick])
