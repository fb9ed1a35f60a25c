"""pictures.py OUT.png: four tuning instances main's 2-means split cuts (split_separation 4.0), two that are one car
cut in two and two that are a hidden car split off a nearer one, chosen with near-equal split features (separation
4.2-4.7 std, vote gap / pixel gap 0.26-0.39). One row each: the input; main's proposals (split on); the same grouping
with the split off; the ground-truth instances (an oracle, drawn only to show which car is which). Every proposal a
colour; the split instance's true cars outlined in white. Raw outputs: frag40's raw.py
(/tmp/s26data/frag40/raw, w0, 312x96). Run from the worktree root with PYTHONPATH=src."""
import sys

import matplotlib
import numpy as np
import torch
from scipy import ndimage

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = [("35", "vkitti1/0001/clone/00035", "one car cut in two (3567 px, sep 4.20)"),
         ("31", "vkitti1/0002/clone/00033", "one car cut in two (2678 px, sep 4.16)"),
         ("37", "vkitti1/0002/clone/00039", "two cars, one hiding the other (6532 px, sep 4.65)"),
         ("13", "vkitti1/0001/clone/00035", "two cars, one hiding the other (4688 px, sep 4.32)")]


def group(fr: dict, things: list[int], split: float | None) -> np.ndarray:
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things,
                          thing_odds=G["thing_odds"], threshold=G["center_threshold"], nms_kernel=G["nms_kernel"],
                          top_k=G["top_k"], min_area=G["min_area"], split_separation=split,
                          part_separation=G["part_separation"])[0][0].numpy()


def overlay(image: np.ndarray, inst: np.ndarray, outline: list[np.ndarray]) -> np.ndarray:
    out = image.astype(float) / 255
    for p in np.unique(inst):
        if p > 0:  # a colour per id, the same id the same colour in every panel
            out[inst == p] = 0.45 * out[inst == p] + 0.55 * np.random.default_rng(int(p)).uniform(0.2, 1.0, 3)
    for car in outline:
        out[car & ~ndimage.binary_erosion(car)] = 1.0
    return out


def main(path: str) -> None:
    fig, axes = plt.subplots(len(CASES), 4, figsize=(16.8, 1.8 * len(CASES) + 0.6))
    for row, (seed, key, what) in enumerate(CASES):
        raw = torch.load(f"/tmp/s26data/frag40/raw/raw{seed}.pt", weights_only=False)
        fr = raw["frames"][key]
        image = fr["image"].permute(1, 2, 0).numpy()
        if image.dtype != np.uint8:
            image = (np.clip(image, 0, 1) * 255).astype(np.uint8)
        split, whole = group(fr, raw["things"], G["split_separation"]), group(fr, raw["things"], None)
        top_k = G["top_k"]
        second = [p for p in np.unique(split) if top_k < p % INSTANCE_DIVISOR <= 2 * top_k]
        gt = fr["gt_instances"].numpy()
        cars = set()
        for p in second:  # the true cars under both parts of each split
            k = p % INSTANCE_DIVISOR - top_k  # the first part: centre k, whatever class its majority gave it
            for part in (split == p, (split % INSTANCE_DIVISOR == k) & (split > 0)):
                ids, n = np.unique(gt[part], return_counts=True)
                cars.add(int(ids[n.argmax()]))
        outline = [gt == c for c in cars if c >= INSTANCE_DIVISOR]
        axes[row, 0].imshow(image)
        axes[row, 0].set_title(f"tree {seed} {key[8:]}:\n{what}", fontsize=8)
        axes[row, 1].imshow(overlay(image, split, outline))
        axes[row, 1].set_title("main df7269b: 2-means split on (4.0)", fontsize=8)
        axes[row, 2].imshow(overlay(image, whole, outline))
        axes[row, 2].set_title("main df7269b with the split off", fontsize=8)
        axes[row, 3].imshow(overlay(image, np.where(gt >= INSTANCE_DIVISOR, gt, 0), outline))
        axes[row, 3].set_title("ground-truth instances (oracle)", fontsize=8)
    for ax in axes.flat:
        ax.axis("off")
    fig.suptitle("Main's 2-means splits: a colour per proposal; white: the split instance's true cars (oracle outline)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=80)


if __name__ == "__main__":
    main(sys.argv[1])
