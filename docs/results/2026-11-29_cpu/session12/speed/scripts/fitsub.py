# ruff: noqa
"""fitsub.py INPUTS N MIRROR: the fit on the first N captured objects (threads 1), mirror on/off; CPU s of two runs."""
import sys, time, torch
torch.set_num_threads(1)
import sdn3d.geometric.fit as fit
a = dict(torch.load(sys.argv[1], weights_only=False)); n = int(sys.argv[2])
masks, boxes, intr = a.pop("masks")[:n], a.pop("boxes")[:n], a.pop("intr")
a = {k: (v[:n] if torch.is_tensor(v) or isinstance(v, list) else v) for k, v in a.items()}
first = torch.where(torch.isfinite(a["start_ry"]), a["start_ry"], torch.full_like(a["start_ry"], -1.5708))
s = fit.FitSettings(mirror=sys.argv[3] == "1")
for _ in range(2):
    t = time.process_time()
    fit.fit_to_masks(masks, boxes, intr, settings=s, yaw_belief=lambda ry: torch.cos(ry - first[:, None]), **a)
    print(f"objects {n} mirror {sys.argv[3]} fit cpu {time.process_time() - t:.2f}", flush=True)
