# ruff: noqa: E402, E501, E701, E702
"""ana.py CAP.pt...: per weather, the lamp cue's reading against the truth (back seen: sin(alpha_true) < 0) and the
facing belief's verdict at the true axis (score(true ry) vs score(true ry + pi)); variant via env VAR."""
import math
import os
import sys

import torch

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.lamps import LampCue, red_lamps, white_lamps

sys.path.insert(0, "/tmp/s9data/fogflip")

for f in sys.argv[1:]:
    rows = torch.load(f, weights_only=False)
    by = {}
    for r in rows: by.setdefault(r["key"][1], []).append(r)
    for w, rr in sorted(by.items()):
        seen = torch.stack([r["seen"] for r in rr]).float(); lamps = torch.stack([r["lamps"] for r in rr]).float()
        cd = os.environ.get("CD", "0.15")
        cue = LampCue(clear_dark=None if cd == "none" else float(cd))
        present, usable, offset = red_lamps(seen, lamps, cue)
        fp, fu, fo = white_lamps(seen, lamps, cue)
        true = torch.tensor([r["true_ry"] for r in rr]); ray = torch.stack([r["ray"] for r in rr])
        alpha = true - ray; back = torch.sin(alpha) < 0
        ap = {"net_ry": torch.stack([r["net_ry"] for r in rr]), "ray": ray, "lamp_present": present, "lamp_usable": usable, "lamp_offset": offset,
              "front_present": fp, "front_usable": fu, "front_offset": fo}
        if "yaw_bins" in rr[0]: ap |= {k: torch.stack([r[k] for r in rr]) for k in ("yaw_bins", "yaw_residual", "yaw_ray")}
        s = facing_belief(ap, cue)(torch.stack([true, true + math.pi], 1).double())
        wrong = s[:, 0] < s[:, 1]
        us = usable
        side = (torch.sin(alpha).abs() > 0.3)
        print(f"CD {cd:4s} {f.split('/')[-1]:10s} {w:6s} n {len(rr):3d} usable {int(us.sum()):3d} | back&present {int((us & back & present).sum()):3d} back&absent {int((us & back & ~present).sum()):3d} front&present {int((us & ~back & present).sum()):3d} front&absent {int((us & ~back & ~present).sum()):3d} | belief wrong end {int(wrong.sum()):3d} | red-body usable {int((fu & ~us).sum())} front&white {int((fu & ~us & ~back & fp).sum())}/{int((fu & ~us & ~back).sum())} back&white {int((fu & ~us & back & fp).sum())}/{int((fu & ~us & back).sum())}")
