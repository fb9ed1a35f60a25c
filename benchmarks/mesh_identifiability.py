"""How much the reprojection reward can tell the mesh templates apart, and the floors of mesh accuracy; prints JSON.

    python benchmarks/mesh_identifiability.py [--root /work/data/synth] [--crop-sizes 64 128] [--split test]

REINFORCE picks the template whose silhouette best matches the object's mask. This measures the ceiling
that reward sets, independently of any training: every object of the split is rendered with each of the
8 templates at its **ground-truth** dims, yaw and centre (no FFD), in its own crop camera, and each
template's soft L_reproj (:func:`sdn3d.geometric.metrics.template_reprojection_errors`, the training loss,
closer objects and pixels outside the image ignored) is computed. Reported per crop size:

- ``true_is_best``: share of objects whose true template has the lowest L_reproj. This is the mesh
  accuracy a perfect pose predictor with a perfect reward-maximising policy would reach; the geometric
  module logs the same figure on its test objects as ``test/mesh_identifiability_ceiling``.
- ``true_error`` / ``best_error``: mean L_reproj of the true template / of the best one.
- ``gap_best_second``: mean L_reproj gap between the best and the second-best template. It is the
  reward difference REINFORCE must detect, next to the error that pose mistakes add.
- ``true_image_error``: Table 2's reprojection error (hard silhouette, mismatching pixels of the crop window
  over the W x H frame, :func:`sdn3d.geometric.metrics.image_reprojection_error`) of the true template at the
  true pose without FFD: what a perfect pose scores with undeformed templates (the synthetic cars are deformed).
- the counts of true templates and of best templates.

And the floors of mesh accuracy on the split: ``uniform_floor`` (1/8) and ``majority_floor`` (always the
most frequent template of the *training* part, :func:`sdn3d.geometric.metrics.mesh_floors`).

On synthetic data generated with ``vehicles: bank`` the cars are the templates themselves with a random
FFD, so a template other than the true one can fit the mask better. With ``vehicles: heldout`` (the default)
they are held-out family shapes (:mod:`sdn3d.meshes.vehicle_family`) and the "true template" of an object is
its shape's approximating template (the readers' mapping, :func:`sdn3d.data.datasets.geometric.template_id`):
``true_is_best`` then measures how often the reward prefers that approximation. The output names the data's
``vehicles`` setting (from ``synth_manifest.json``; ``null`` for data without one, e.g. real Virtual KITTI).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import torch
from omegaconf import OmegaConf

from datamodules import GeometricDataModule
from sdn3d.geometric.losses import outside_image_mask
from sdn3d.geometric.metrics import (
    image_reprojection_error,
    mesh_floors,
    template_reprojection_errors,
    window_silhouettes,
)
from sdn3d.meshes import MeshBank

REPO = Path(__file__).resolve().parents[1]


def _datamodule(root: str, crop_size: int) -> GeometricDataModule:
    data = OmegaConf.load(REPO / "conf" / "data" / "synth.yaml")
    data.root = str(root)
    return GeometricDataModule(data, crop_size=crop_size)


def _template_ids(dataset) -> torch.Tensor:
    """True template ids of a guarded geometric dataset's objects, from its records (no image is read)."""
    from sdn3d.data.datasets.geometric import template_id

    inner = getattr(dataset, "dataset", dataset)
    return torch.tensor([template_id(inner.records[ref.frame].objects[ref.object].model) for ref in inner.objects],
                        dtype=torch.long)


def _vehicles(root: str) -> str | None:
    """The ``vehicles`` setting a synthetic dataset was generated with (``'bank'`` before the setting existed)."""
    manifest = Path(root) / "synth_manifest.json"
    if not manifest.is_file():
        return None
    return json.loads(manifest.read_text()).get("config", {}).get("vehicles", "bank")


def identifiability(dm: GeometricDataModule, split: str, batch: int = 64) -> dict:
    ds = dm.datasets[split]
    bank = MeshBank.templates()
    size, image_size = dm.crop_size, dm.image_size
    errors, image_errors, truth = [], [], []
    for start in range(0, len(ds), batch):  # batches of objects, every template at once per batch
        items = torch.utils.data.default_collate([ds[i] for i in range(start, min(start + batch, len(ds)))])
        ignore = torch.maximum(items["ignore"], outside_image_mask(items["crop_box"], image_size, size))
        errors.append(template_reprojection_errors(bank, items["dims"], items["ry"], items["center"], None,
                                                   items["crop_intrinsics"], items["mask"], ignore, size))
        known = items["template_id"].clamp(min=0)
        sil = window_silhouettes(bank, known, items["dims"], items["ry"], items["center"], None, items["intrinsics"],
                                 items["crop_box"], image_size)
        image_errors.append(image_reprojection_error(sil, items["mask"], items["ignore"], items["crop_box"],
                                                     image_size))
        truth.append(items["template_id"])
    err, tid, image_err = torch.cat(errors), torch.cat(truth), torch.cat(image_errors)
    known = tid >= 0
    err, tid, image_err = err[known], tid[known], image_err[known]
    ranked = err.sort(1).values
    best = err.argmin(1)
    return {"crop_size": size, "objects": int(known.sum()),
            "true_is_best": round(float((best == tid).float().mean()), 4),
            "true_error": round(float(err.gather(1, tid[:, None]).mean()), 5),
            "best_error": round(float(ranked[:, 0].mean()), 5),
            "gap_best_second": round(float((ranked[:, 1] - ranked[:, 0]).mean()), 5),
            "true_image_error": round(float(image_err.mean()), 6),
            "true_counts": torch.bincount(tid, minlength=len(bank)).tolist(),
            "best_counts": torch.bincount(best, minlength=len(bank)).tolist(),
            "templates": list(bank.names)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--root", default="/work/data/synth")
    p.add_argument("--crop-sizes", type=int, nargs="+", default=[64, 128])
    p.add_argument("--split", default="test", choices=["train", "val", "test"])
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    results = []
    for crop_size in args.crop_sizes:
        dm = _datamodule(args.root, crop_size)
        dm.setup(None)  # every part: the floors need the training part's templates
        results.append(identifiability(dm, args.split))
    train_ids = _template_ids(dm.datasets["train"])
    train_counts = torch.bincount(train_ids[train_ids >= 0], minlength=8)
    split_ids = _template_ids(dm.datasets[args.split])
    floors = mesh_floors(torch.bincount(split_ids[split_ids >= 0], minlength=8), train_counts)
    out = {"root": args.root, "vehicles": _vehicles(args.root), "split": args.split, "image_size": list(dm.image_size),
           "what": "ground-truth pose, no FFD, each of the 8 templates",
           "floors": {k: round(float(v), 4) for k, v in floors.items()},
           "train_counts": train_counts.tolist(), "results": results}
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
