# ruff: noqa: E402, E501, E701, E702
"""fp.py CAP.pt CD: crops where the through-the-air red test reads lamps on a front view, or where old and new differ."""
import math
import sys

import torch

from sdn3d.geometric.lamps import LampCue, air_offset, red_lamps

rows = torch.load(sys.argv[1], weights_only=False)
cd = float(sys.argv[2])
for r in rows:
    seen = r["seen"].float()[None]; lm = r["lamps"].float()[None]
    old = [v[0].item() for v in red_lamps(seen, lm, LampCue(clear_dark=None))]
    new = [v[0].item() for v in red_lamps(seen, lm, LampCue(clear_dark=cd))]
    back = math.sin(r["true_ry"] - float(r["ray"])) < 0
    if old[:2] != new[:2] or (new[0] and new[1] and not back):
        air, t = air_offset(seen, lm[:, 0] > 0.5, cd)
        print(r["key"], "BACK" if back else "front", "px", r["px"], "old", [round(v, 2) for v in old], "new", [round(v, 2) for v in new], "air", [round(v, 2) for v in air[0].tolist()], "t", round(float(t), 2))
