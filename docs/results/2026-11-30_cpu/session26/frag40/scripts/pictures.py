"""pictures.py OUT.png: the tuning frames whose proposals the join changes, one row each: the input, main's
proposals, the branch's (merge_reach 0.3, merge_separation 2.5) and the wider variant's (0.5, 3.0; not chosen), each
proposal a colour, with the changed true car's outline (the tree's ground-truth instance mask: an oracle, drawn only
to show which car) in white. Raw outputs from raw.py (/tmp/s26data/frag40/raw). Run with PYTHONPATH=<branch>/src."""
import sys

import matplotlib
import numpy as np
import torch
from scipy import ndimage

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = [("37", "vkitti1/0001/clone/00036", 12009), ("11", "vkitti1/0001/clone/00036", 12011),
         ("13", "vkitti1/0001/clone/00039", 13007), ("35", "vkitti1/0001/clone/00034", 12011)]
CODES = [("main 9fa5234 (no join)", None, 2.5), ("branch: join reach 0.3, sep 2.5", 0.3, 2.5),
         ("wider join 0.5 / 3.0 (not chosen)", 0.5, 3.0)]


def group(fr: dict, things: list[int], reach: float | None, sep: float) -> np.ndarray:
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things,
                          thing_odds=G["thing_odds"], threshold=G["center_threshold"], nms_kernel=G["nms_kernel"],
                          top_k=G["top_k"], min_area=G["min_area"], split_separation=G["split_separation"],
                          part_separation=G["part_separation"], merge_reach=reach,
                          merge_separation=sep)[0][0].numpy()


def overlay(image: np.ndarray, inst: np.ndarray, car: np.ndarray) -> np.ndarray:
    out = image.astype(float) / 255
    for p in np.unique(inst):
        if p > 0:  # a colour per proposal id, the same id the same colour in every panel
            out[inst == p] = 0.45 * out[inst == p] + 0.55 * np.random.default_rng(int(p)).uniform(0.2, 1.0, 3)
    edge = car & ~ndimage.binary_erosion(car)
    out[edge] = 1.0
    return out


fig, axes = plt.subplots(len(CASES), 1 + len(CODES), figsize=(4.2 * (1 + len(CODES)), 1.6 * len(CASES) + 0.6))
for row, (seed, key, car_id) in enumerate(CASES):
    raw = torch.load(f"/tmp/s26data/frag40/raw/raw{seed}.pt", weights_only=False)
    fr = raw["frames"][key]
    image = fr["image"].permute(1, 2, 0).numpy()
    car = (fr["gt_instances"] == car_id).numpy()
    axes[row, 0].imshow(image)
    axes[row, 0].set_title(f"tree {seed} {key[8:]} input", fontsize=8)
    for col, (name, reach, sep) in enumerate(CODES, 1):
        inst = group(fr, raw["things"], reach, sep)
        on = [p for p in np.unique(inst[car]) if p > 0 and (inst[car] == p).sum() >= 0.5 * (inst == p).sum()]
        axes[row, col].imshow(overlay(image, inst, car))
        axes[row, col].set_title(f"{name}: {len(on)} proposal(s) on the outlined car", fontsize=8)
for ax in axes.flat:
    ax.axis("off")
fig.suptitle("Proposals (a colour each) on the tuning cars the join changes; white: the true car (oracle outline)",
             fontsize=10)
fig.tight_layout()
fig.savefig(sys.argv[1], dpi=80)
