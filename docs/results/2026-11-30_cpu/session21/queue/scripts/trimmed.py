# ruff: noqa: E501, E701, E702
"""trimmed.py RAW.pt... : scouting a robust split (no code behind it): _split_parts' 2-means statistic on each final
proposal of main's grouping (GROUPING_DEFAULTS) after leaving out its far votes (farther from the median vote than
TRIM times the median vote distance), by cars held (oracle, hidden's 30 % rule), and what a threshold on it would cut.
Run from the worktree root with PYTHONPATH=src on session 21 hidden's raw.py files (tuning trees 35/37/31 at 312x96)."""
import sys

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

torch.set_num_threads(1)


def stat(v):
    d = v - v.mean(0); cov = d.T @ d / len(d)
    ang = 0.5 * torch.atan2(2 * cov[0, 1], cov[0, 0] - cov[1, 1]); s = d[:, 0] * ang.cos() + d[:, 1] * ang.sin()
    cut = torch.tensor(0.0)
    for _ in range(16):
        hi = s > cut
        if hi.all() or (~hi).all(): return 0.0
        cut = (s[hi].mean() + s[~hi].mean()) / 2
    hi = s > cut; r = torch.where(hi, s - s[hi].mean(), s - s[~hi].mean())
    return float((s[hi].mean() - s[~hi].mean()) / (((r[hi] ** 2).mean() + (r[~hi] ** 2).mean()) / 2).sqrt().clamp_min(0.5))


rows = {2.0: [], 3.0: []}
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
            dist = (v - v.median(0).values).norm(dim=-1); scale = dist.median().clamp_min(0.5)
            for trim in rows: rows[trim].append((n, stat(v[dist <= trim * scale])))
for trim, rr in rows.items():
    t = torch.tensor(rr); one, two = t[t[:, 0] == 1, 1], t[t[:, 0] >= 2, 1]
    for lab, x in (("1 car", one), ("2+ cars", two)):
        q = torch.quantile(x, torch.tensor([.25, .5, .75, .9])).tolist()
        print(f"trim {trim}: {lab:8s} {len(x):4d} proposals, trimmed statistic q25/50/75/90 " + " ".join(f"{v:.2f}" for v in q))
    for T in (3.5, 4.0, 4.5):
        print(f"trim {trim}: statistic >= {T}: cuts {int((one >= T).sum())} 1-car, {int((two >= T).sum())} 2+-car proposals")
