# ruff: noqa: E402, E501, E701, E702
"""Run sdn3d-edit once and save fit_to_masks' inputs (the yaw belief evaluated lazily is kept as a callable: pickled by torch.save? no: saved as None-free dict of tensors plus the belief's table)."""
import sys

import torch

import sdn3d.geometric.fit as fit

inner = fit.fit_to_masks
def grab(masks, boxes, intr, **kw):
    r = inner(masks, boxes, intr, **kw)
    kw = dict(kw); belief = kw.pop("yaw_belief", None)
    torch.save({"masks": masks, "boxes": boxes, "intr": intr, **{k: v for k, v in kw.items() if k not in ("bank", "settings")}}, sys.argv[1])
    globals()["BELIEF"] = belief
    return r
fit.fit_to_masks = grab
import sdn3d.cli.edit as edit

edit.main(sys.argv[2:])
