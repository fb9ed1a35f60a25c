# ruff: noqa
import sys, time, torch, cProfile, pstats
torch.set_num_threads(1)
import sdn3d.geometric.fit as fit
a = dict(torch.load(sys.argv[1], weights_only=False))
masks, boxes, intr = a.pop("masks"), a.pop("boxes"), a.pop("intr")
first = torch.where(torch.isfinite(a["start_ry"]), a["start_ry"], torch.full_like(a["start_ry"], -1.5708))
def belief(ry):
    return torch.cos(ry - first[:, None])
fit.fit_to_masks(masks[:2], boxes[:2], intr, yaw_belief=lambda r: torch.cos(r - first[:2, None]), **{k: (v[:2] if torch.is_tensor(v) else v[:2] if isinstance(v, list) else v) for k, v in a.items()})
pr = cProfile.Profile(); pr.enable()
r = fit.fit_to_masks(masks, boxes, intr, yaw_belief=belief, **a)
pr.disable()
pstats.Stats(pr).sort_stats("tottime").print_stats(25)
