"""pictures.py OUT_DIR tuning|heldout: session 27 join40's labelled pictures (312x96, w0, predicted proposals), of the
tuning trees or of held-out tree 2263 (file names end ``_heldout2263`` there).

1. ``proposals_joined_tuning.png``: every frame where the branch joins proposals, one row each: the input;
   main's proposals; the branch's (a colour per proposal id; white: the true cars' outlines, ground truth, an
   oracle used only to show where the cars are).
2. ``edits_joined_tuning.png``: Table 1 entries whose source frame has a join (dbench.py's dumps of main's and the
   branch's runs): the source, the target, 3D-SDN's photo result on main and on the branch, with each one's PSNR
   *all* (results.json).
Inputs: frag40's raw files (image, ground-truth instances; raw.py's for 2263), the de-render caches (main: frag40's
cache<SEED>main, /tmp/s27data/join40/t1/cache2263main on 2263; branch: /tmp/s27data/join40/t1/cache<SEED>br) and
the runs' dumps. Run: PYTHONPATH=<branch>/src python pictures.py OUT
"""
import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import torch  # noqa: E402

T1 = "/tmp/s27data/join40/t1"
FRAMES = [("37", "vkitti1/0001/clone/00036"), ("37", "vkitti1/0001/rain/00036"), ("37", "vkitti1/0001/rain/00037"),
          ("11", "vkitti1/0001/clone/00037"), ("13", "vkitti1/0001/clone/00039"), ("31", "vkitti1/0002/clone/00033"),
          ("39", "vkitti1/0002/rain/00037")]
EDITS = [("37", 45), ("11", 22), ("37", 44), ("37", 53)]  # a delete, two gains, the largest loss
HELD_FRAMES = [("2263", "vkitti1/0001/rain/00037"), ("2263", "vkitti1/0002/clone/00033")]
HELD_EDITS = [("2263", 44), ("2263", 48), ("2263", 53), ("2263", 83)]  # every entry that changed


def raw_path(tree: str) -> str:
    return "/tmp/s27data/join40/raw2263.pt" if tree == "2263" else f"/tmp/s26data/frag40/raw/raw{tree}.pt"


def main_cache(tree: str) -> str:
    return f"{T1}/cache2263main" if tree == "2263" else f"/tmp/s26data/frag40/t1/cache{tree}main"


def scenes(cache: str) -> dict:
    out = {}
    for p in glob.glob(f"{cache}/*.pt"):
        s = torch.load(p, weights_only=False)
        if s.meta.get("proposals") == "semantic":
            out[s.meta["source"]] = s
    return out


def colours(inst: np.ndarray) -> np.ndarray:
    """A colour per proposal id (stable: hashed from the id), black background."""
    out = np.zeros((*inst.shape, 3))
    for i in np.unique(inst):
        if i > 0:
            rng = np.random.default_rng(int(i) * 7919 % 100003)
            out[inst == i] = 0.25 + 0.75 * rng.random(3)
    return out


def outline(ax, gt: np.ndarray) -> None:
    for i in np.unique(gt):
        if i >= 12000:
            ax.contour(gt == i, levels=[0.5], colors="white", linewidths=0.6)


def proposals_map(scene) -> np.ndarray:
    o = scene.objects
    return (o.mask.long() * o.instance_id[:, None, None]).sum(0).numpy()


def picture_proposals(out: str, frames: list, suffix: str) -> None:
    main, br, raws = {}, {}, {}
    fig, axes = plt.subplots(len(frames), 3, figsize=(15, 1.75 * len(frames) + 0.4), squeeze=False)
    for r, (tree, key) in enumerate(frames):
        if tree not in raws:
            raws[tree] = torch.load(raw_path(tree), weights_only=False)
            main[tree], br[tree] = scenes(main_cache(tree)), scenes(f"{T1}/cache{tree}br")
        fr = raws[tree]["frames"][key]
        gt = fr["gt_instances"].numpy()
        m, b = main[tree][key], br[tree][key]
        joined = [f"{f['joined_from']}" for f in b.meta["fits"] if f.get("joined_from")]
        panels = [(fr["image"].permute(1, 2, 0).numpy(), f"input: tree {tree} {key[8:]}"),
                  (colours(proposals_map(m)), f"main 9bee856: {len(m.objects.instance_id)} proposals"),
                  (colours(proposals_map(b)),
                   f"branch: {len(b.objects.instance_id)} proposals, joined {', '.join(joined)}")]
        for c, (img, title) in enumerate(panels):
            ax = axes[r, c]
            ax.imshow(img)
            if c:
                outline(ax, gt)
            ax.set_title(title, fontsize=8)
            ax.axis("off")
    fig.suptitle("Predicted proposals (w0, 312x96): a colour per proposal; white: true cars' outlines "
                 "(ground truth, oracle, shown only)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"proposals_joined_{suffix}.png"), dpi=70)


def psnr(run: str, index: int) -> tuple[str, float]:
    for e in list(json.load(open(f"{run}/results.json"))["entries"].values())[0]:
        if e["index"] == index:
            return e["edit_kind"], e["metrics"]["photo"]["3d-sdn"]["all"]["psnr"]
    raise KeyError(index)


def picture_edits(out: str, edits: list, suffix: str) -> None:
    fig, axes = plt.subplots(len(edits), 4, figsize=(20, 1.75 * len(edits) + 0.4), squeeze=False)
    for r, (tree, index) in enumerate(edits):
        a = np.load(f"{T1}/main{tree}_semantic.dump/{index:04d}.npz")
        b = np.load(f"{T1}/br{tree}_semantic.dump/{index:04d}.npz")
        kind, pm = psnr(f"{T1}/main{tree}_semantic", index)
        _, pb = psnr(f"{T1}/br{tree}_semantic", index)
        panels = [(a["source"], f"source: tree {tree} entry {index} ({kind}), {a['key']}"), (a["target"], "target"),
                  (a["sdn"], f"3D-SDN photo, main 9bee856: PSNR all {pm:.2f} dB"),
                  (b["sdn"], f"3D-SDN photo, branch (joined): PSNR all {pb:.2f} dB")]
        for c, (img, title) in enumerate(panels):
            axes[r, c].imshow(img)
            axes[r, c].set_title(title, fontsize=8)
            axes[r, c].axis("off")
    fig.suptitle("Table 1 entries whose source frame has a join (predicted proposals, w0, 312x96)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, f"edits_joined_{suffix}.png"), dpi=50)


if __name__ == "__main__":
    held = sys.argv[2] == "heldout"
    picture_proposals(sys.argv[1], HELD_FRAMES if held else FRAMES, "heldout2263" if held else "tuning")
    picture_edits(sys.argv[1], HELD_EDITS if held else EDITS, "heldout2263" if held else "tuning")
