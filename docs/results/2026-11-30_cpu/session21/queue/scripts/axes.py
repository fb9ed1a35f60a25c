# ruff: noqa: E501, E701, E702
"""axes.py RAW.pt... : scouting (no code behind it) the 2-means statistic along other axes than the principal one, on
every final proposal of main's grouping (GROUPING_DEFAULTS; at least 32 px), by cars held (oracle, hidden's 30 % rule):
the principal axis (what _split_parts uses), the minor axis, and the best of 12 directions (each side >= 16 px).
Prints quartiles (25, 50, 75, 90 %) and how many proposals a threshold would cut. Run from the worktree root with
PYTHONPATH=src on session 21 hidden's raw.py files (tuning trees 35/37/31 at 312x96)."""
import math
import sys

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

torch.set_num_threads(1)
def stat1(s):
    cut = s.mean()
    for _ in range(16):
        hi = s > cut
        if hi.all() or (~hi).all(): return 0.0, hi
        cut = (s[hi].mean() + s[~hi].mean()) / 2
    hi = s > cut; r = torch.where(hi, s - s[hi].mean(), s - s[~hi].mean())
    return float((s[hi].mean() - s[~hi].mean()) / (((r[hi] ** 2).mean() + (r[~hi] ** 2).mean()) / 2).sqrt().clamp_min(0.5)), hi
rows = []
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]
    for fr in raw["frames"].values():
        prob = fr["logits"].float().softmax(0)[None]
        inst = group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=G["thing_odds"],
                              threshold=G["center_threshold"], nms_kernel=G["nms_kernel"], top_k=G["top_k"], min_area=G["min_area"],
                              split_separation=G["split_separation"], part_separation=G["part_separation"])[0][0]
        gi = fr["gt_instances"]; h, w = gi.shape
        vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
        vote = torch.stack([uu + fr["offset"][0], vv + fr["offset"][1]], -1)
        cars = [gi == c for c in gi.unique().tolist() if c >= 1000 and c // 1000 in things and int((gi == c).sum()) >= 16]
        for i in inst.unique().tolist():
            if i <= 0: continue
            P = inst == i; v = vote[P]
            if len(v) < 32: continue
            n = sum(int((P & m).sum()) >= max(16, 0.3 * int(m.sum())) for m in cars)
            d = v - v.mean(0); cov = d.T @ d / len(d)
            ang = 0.5 * math.atan2(2 * float(cov[0, 1]), float(cov[0, 0] - cov[1, 1]))
            best = 0.0; minor = 0.0; pr = 0.0
            for a in range(12):
                th = a * math.pi / 12
                st, hi = stat1(d[:, 0] * math.cos(th) + d[:, 1] * math.sin(th))
                if min(int(hi.sum()), int((~hi).sum())) >= 16: best = max(best, st)
            minor = stat1(d[:, 0] * math.cos(ang + math.pi / 2) + d[:, 1] * math.sin(ang + math.pi / 2))[0]
            pr = stat1(d[:, 0] * math.cos(ang) + d[:, 1] * math.sin(ang))[0]
            rows.append((n, pr, minor, best, path[-10:-8]))
t = torch.tensor([r[:4] for r in rows])
one, two = t[t[:, 0] == 1], t[t[:, 0] >= 2]
for name, c in (("principal", 1), ("minor", 2), ("best of 12 axes", 3)):
    for lab, x in (("1", one), ("2+", two)):
        q = torch.quantile(x[:, c], torch.tensor([.25, .5, .75, .9])).tolist()
        print(name, lab, " ".join(f"{v:.2f}" for v in q))
    for T in (3.5, 4.0, 4.5, 5.0):
        print("   ", T, "cuts 1-car", int((one[:, c] >= T).sum()), "2+", int((two[:, c] >= T).sum()))
