# ruff: noqa: E501, E701, E702
"""other_stats.py RAW.pt... : two more candidate statistics for a second split round, on every final proposal of main's
grouping (GROUPING_DEFAULTS; at least 32 px), by cars held (oracle, hidden's 30 % rule): the 2-means statistic, a
valley-to-peak ratio (votes within a quarter of the cluster gap of the cut, over the emptier cluster mean's) and the
share of the proposal's pixels with a 4-neighbour in it on the other side of the cut. Prints quartiles (10, 25, 50, 75, 90
%) and how many proposals a rule stat >= T, valley ratio <= D, mixing <= M would select. Run from the worktree root
with PYTHONPATH=src on session 21 hidden's raw.py files (tuning trees 35/37/31 at 312x96)."""
import sys

import torch
import torch.nn.functional as F

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

torch.set_num_threads(1)
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
        pix = torch.stack([uu, vv], -1); vote = pix + fr["offset"].permute(1, 2, 0)
        cars = [gi == c for c in gi.unique().tolist() if c >= 1000 and c // 1000 in things and int((gi == c).sum()) >= 16]
        for i in inst.unique().tolist():
            if i <= 0: continue
            P = inst == i
            n = sum(int((P & m).sum()) >= max(16, 0.3 * int(m.sum())) for m in cars)
            v = vote[P]
            if len(v) < 32: continue
            d = v - v.mean(0); cov = d.T @ d / len(d)
            ang = 0.5 * torch.atan2(2 * cov[0, 1], cov[0, 0] - cov[1, 1]); s = d[:, 0] * ang.cos() + d[:, 1] * ang.sin()
            cut = torch.tensor(0.0)
            for _ in range(16):
                hi = s > cut; cut = (s[hi].mean() + s[~hi].mean()) / 2
            hi = s > cut; mh, ml = s[hi].mean(), s[~hi].mean()
            r = torch.where(hi, s - mh, s - ml); sd = (((r[hi] ** 2).mean() + (r[~hi] ** 2).mean()) / 2).sqrt().clamp_min(0.5)
            st = float((mh - ml) / sd)
            bw = 0.25 * (mh - ml)
            valley = float(((s - cut).abs() < bw).sum()); peak = float(min(((s - mh).abs() < bw).sum(), ((s - ml).abs() < bw).sum()))
            dip = valley / max(peak, 1)
            # spatial mixing: share of the instance's pixels with a 4-neighbour in the instance on the other side
            side = torch.zeros(h, w); side[P] = torch.where(hi, 1.0, -1.0)
            pad = F.pad(side[None, None], (1, 1, 1, 1))[0, 0]
            other = torch.zeros(h, w, dtype=torch.bool)
            for dv, du in ((0, 1), (1, 0), (0, -1), (-1, 0)):
                nb = pad[1 + dv:1 + dv + h, 1 + du:1 + du + w]; other |= (nb * side) < 0
            mix = float(other[P].float().mean())
            rows.append((n, st, dip, mix, int(P.sum())))
t = torch.tensor(rows)
one, two = t[t[:, 0] == 1], t[t[:, 0] >= 2]
for name, col in (("2-means statistic", 1), ("valley-to-peak ratio", 2), ("neighbour mixing", 3)):
    for lab, x in (("1 car", one), ("2+ cars", two)):
        q = torch.quantile(x[:, col], torch.tensor([.1, .25, .5, .75, .9])).tolist()
        print(f"{name:21s} {lab:8s} {len(x):4d} proposals: " + " ".join(f"{v:.3f}" for v in q))
for st in (2.8, 3.0, 3.2):
    for dip in (0.3, 0.5, 1.0):
        for mix in (0.15, 1.0):
            n1, n2 = (int(((x[:, 1] >= st) & (x[:, 2] <= dip) & (x[:, 3] <= mix)).sum()) for x in (one, two))
            print(f"stat >= {st}, valley <= {dip}, mixing <= {mix}: 1-car {n1}, 2+-car {n2}")
