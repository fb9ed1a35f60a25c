# ruff: noqa: E402, E501, E701, E702  (a one-off record script, kept as it ran)
"""Capture fit_cost's fit_to_masks inputs (10 box objects at 624x192, GrabCut masks) on a dense tree."""

import sys
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, "benchmarks")
torch.set_num_threads(1)
import fit_cost
from PIL import Image

import sdn3d.geometric.fit as fit_module
from sdn3d.derender import BoxPrompts, derender
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.models import Models

path, boxes = fit_cost._dense_frame(Path(sys.argv[1]))
boxes = boxes[:10]
image = torch.from_numpy(np.array(Image.open(path).convert("RGB"))).permute(2, 0, 1).float() / 255
intr = VKITTI_INTRINSICS.resized(624, 192)
models = Models.from_checkpoints(geometric="/tmp/h5runs/big_mb40/checkpoints/inference.pt")
cap = []
real = fit_module.fit_to_masks


def fake(masks, boxes, intr, **kw):
    cap.append(
        {
            "masks": masks,
            "boxes": boxes,
            "intr": intr,
            **{k: v for k, v in kw.items() if k not in ("settings", "yaw_belief")},
        }
    )
    return real(masks, boxes, intr, **kw)


fit_module.fit_to_masks = fake
derender(
    image,
    intr,
    models,
    "boxes",
    boxes=BoxPrompts(torch.tensor(boxes, dtype=torch.float32), tuple("Car" for _ in boxes)),
    classes="vkitti",
)
torch.save(cap[0], sys.argv[2])
print(len(cap), cap[0]["masks"].shape)
