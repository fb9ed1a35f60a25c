"""How much the reprojection reward can tell the mesh templates apart; prints JSON.

    python benchmarks/mesh_identifiability.py [--root /work/data/synth] [--crop-sizes 64 128] [--split test]

REINFORCE picks the template whose silhouette best matches the object's mask. This measures the ceiling
that reward sets, independently of any training: every object of the split is rendered with each of the
8 templates at its **ground-truth** dims, yaw and centre (no FFD), in its own crop camera, and each
template's L_reproj (:func:`sdn3d.geometric.losses.reprojection_error`, closer objects ignored) is
computed. Reported per crop size:

- ``true_is_best``: share of objects whose true template has the lowest L_reproj. This is the mesh
  accuracy a perfect pose predictor with a perfect reward-maximising policy would reach.
- ``true_error`` / ``best_error``: mean L_reproj of the true template / of the best one.
- ``gap_best_second``: mean L_reproj gap between the best and the second-best template. It is the
  reward difference REINFORCE must detect, next to the error that pose mistakes add.
- the counts of true templates and of best templates.

The synthetic cars are templates with a random FFD and wheels, so a template other than the true one
can fit the mask better.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import torch
from omegaconf import OmegaConf

from datamodules import GeometricDataModule
from sdn3d.geometric.losses import render_silhouettes, reprojection_error
from sdn3d.meshes import MeshBank

REPO = Path(__file__).resolve().parents[1]


def identifiability(root: str, crop_size: int, split: str, batch: int = 64) -> dict:
    data = OmegaConf.load(REPO / "conf" / "data" / "synth.yaml")
    data.root = str(root)
    dm = GeometricDataModule(data, crop_size=crop_size)
    dm.setup("fit" if split == "train" else "test")
    ds = dm.datasets[split]
    bank = MeshBank.templates()
    t = len(bank)
    errors, truth = [], []
    for start in range(0, len(ds), batch):  # batches of objects, every template at once per batch
        items = torch.utils.data.default_collate([ds[i] for i in range(start, min(start + batch, len(ds)))])
        n = len(items["dims"])
        ids = torch.arange(t).repeat(n)
        rows = {k: items[k].repeat_interleave(t, 0) for k in ("dims", "ry", "center", "crop_intrinsics", "mask",
                                                               "ignore")}  # object rows, one per template
        sil = render_silhouettes(bank, ids, rows["dims"], rows["ry"], rows["center"], None, rows["crop_intrinsics"],
                                 crop_size)
        err = reprojection_error(sil, rows["mask"], rows["ignore"]).view(n, t)
        errors.append(err)
        truth.append(items["template_id"])
    err, tid = torch.cat(errors), torch.cat(truth)
    known = tid >= 0
    err, tid = err[known], tid[known]
    ranked = err.sort(1).values
    best = err.argmin(1)
    return {"crop_size": crop_size, "objects": int(known.sum()),
            "true_is_best": round(float((best == tid).float().mean()), 4),
            "true_error": round(float(err.gather(1, tid[:, None]).mean()), 5),
            "best_error": round(float(ranked[:, 0].mean()), 5),
            "gap_best_second": round(float((ranked[:, 1] - ranked[:, 0]).mean()), 5),
            "true_counts": torch.bincount(tid, minlength=len(bank)).tolist(),
            "best_counts": torch.bincount(best, minlength=len(bank)).tolist(),
            "templates": list(bank.names)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--root", default="/work/data/synth")
    p.add_argument("--crop-sizes", type=int, nargs="+", default=[64, 128])
    p.add_argument("--split", default="test", choices=["train", "test"])
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    out = {"root": args.root, "split": args.split, "what": "ground-truth pose, no FFD, each of the 8 templates",
           "results": [identifiability(args.root, s, args.split) for s in args.crop_sizes]}
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
