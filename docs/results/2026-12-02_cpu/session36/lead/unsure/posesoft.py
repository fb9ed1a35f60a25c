# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
"""posesoft.py ARGS...: benchmarks/pose_table.py where the fit's mask crops are the proposal masks times the semantic
branch's vehicle probability (SOFT=1; SOFT=0: as main). An experiment."""
import os, sys
sys.path.insert(0, "/work/main/benchmarks")
import torch
import sdn3d.geometric.fit as FIT
from sdn3d.semantic.predict import SemanticPredictor
import pose_table
state = {"p": None}
if os.environ.get("SOFT", "0") != "0":
    power = float(os.environ.get("SOFT_POWER", "1"))
    _call = SemanticPredictor.__call__
    def call(self, image, *a, **k):
        seg = _call(self, image, *a, **k)
        things = torch.tensor([c for c in (12, 13) if c < seg.probability.shape[1]])
        state["p"] = seg.probability[0, things].sum(0).float().cpu()
        return seg
    SemanticPredictor.__call__ = call
    _crops = FIT._crops
    def crops(masks, ignore, windows, size, intr, image_size):
        p = state["p"]
        if p is not None and tuple(p.shape) == tuple(masks.shape[-2:]) and not masks.is_floating_point():
            if os.environ.get("SOFT_MODE") == "ignore":
                lo, hi = float(os.environ.get("SOFT_LO", "0.3")), float(os.environ.get("SOFT_HI", "0.7"))
                unsure = (p > lo) & (p < hi)
                cap = os.environ.get("SOFT_CAP")
                if cap:  # objects whose mask is more than this share unsure: nothing left out
                    m = masks.bool()
                    share = (m & unsure[None]).flatten(1).sum(1) / m.flatten(1).sum(1).clamp(min=1)
                    ignore = ignore.bool() | (unsure[None] & (share <= float(cap))[:, None, None])
                else:
                    ignore = ignore.bool() | unsure[None]
            else:
                masks = masks.float() * p[None].clamp(0, 1) ** power
        return _crops(masks, ignore, windows, size, intr, image_size)
    FIT._crops = crops
pose_table.main(sys.argv[1:])
