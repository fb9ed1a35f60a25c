# ruff: noqa: E501, E701, E702
"""why_split.py RAW.pt... : why main's 2-means split leaves queue pairs merged. Run from the worktree root with
PYTHONPATH=src, OMP_NUM_THREADS=1, on session 21 hidden's raw.py files (/tmp/s21data/hidden/raw{35,37,31}_312.pt: a
Table 1 tuning tree's source frames at 312x96, this session's demo weights). The ground truth is an oracle, used for
scoring only.

For every proposal of main's grouping (group_vehicles, GROUPING_DEFAULTS) that *holds* two or more ground-truth cars
(hidden's merged.py rule: >= 30 % and >= 16 px of each Car / Van of >= 16 px), take the nearest-centre instance it came
from (the grouping without the split and the part rule: what _split_parts sees) and redo _split_parts' 1-D 2-means on its
votes: the statistic (pooled-SD separation of the two clusters' means), each side's pixels, sure (arg-max thing) pixels
and ground-truth car pixels, and whether the split fired (both sides >= min_area sure pixels and statistic >= 4).
Then the statistic on the merged proposal's own pixels (what a second split round would see).
Last, the same statistic on every final proposal, by how many cars it holds (0, 1, 2+): can any threshold on it, or on
the ratio of the halves' vote-mean gap to their pixel-centroid gap, part the pairs without cutting single cars?
Prints one line a merged proposal and the summaries."""
import sys

import torch

from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS as G

torch.set_num_threads(1)


def group(fr, things, split, part):
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=G["thing_odds"],
                          threshold=G["center_threshold"], nms_kernel=G["nms_kernel"], top_k=G["top_k"], min_area=G["min_area"],
                          split_separation=split, part_separation=part)[0][0]


def two_means(v, p):
    """_split_parts' statistic on votes v (N, 2): (stat, high side bool (N,), vote-gap / pixel-gap ratio); p (N, 2) pixels."""
    d = v - v.mean(0); cov = d.T @ d / len(d)
    ang = 0.5 * torch.atan2(2 * cov[0, 1], cov[0, 0] - cov[1, 1])
    s = d[:, 0] * ang.cos() + d[:, 1] * ang.sin(); cut = torch.tensor(0.0)
    for _ in range(16):
        hi = s > cut
        if hi.all() or (~hi).all(): return 0.0, hi, 0.0
        cut = (s[hi].mean() + s[~hi].mean()) / 2
    hi = s > cut
    r = torch.where(hi, s - s[hi].mean(), s - s[~hi].mean())
    st = float((s[hi].mean() - s[~hi].mean()) / (((r[hi] ** 2).mean() + (r[~hi] ** 2).mean()) / 2).sqrt().clamp_min(0.5))
    ratio = float((v[hi].mean(0) - v[~hi].mean(0)).norm() / (p[hi].mean(0) - p[~hi].mean(0)).norm().clamp_min(1e-6))
    return st, hi, ratio


allrows = []; merged = []
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]; tree = path.split("raw")[-1][:2]
    for key, fr in raw["frames"].items():
        inst = group(fr, things, G["split_separation"], G["part_separation"]); pre = group(fr, things, None, None)
        gi = fr["gt_instances"]; h, w = gi.shape
        vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
        pix = torch.stack([uu, vv], -1); vote = pix + fr["offset"].permute(1, 2, 0)
        sure = torch.isin(fr["logits"].float().argmax(0), torch.tensor(things))
        car = gi >= 1000
        cars = [gi == c for c in gi.unique().tolist() if c >= 1000 and c // 1000 in things and int((gi == c).sum()) >= 16]
        for i in inst.unique().tolist():
            if i <= 0: continue
            P = inst == i
            n = sum(int((P & m).sum()) >= max(16, 0.3 * int(m.sum())) for m in cars)
            st, hi, ratio = two_means(vote[P], pix[P])
            allrows.append((n, st, ratio, int(min(hi.sum(), (~hi).sum()))))
            if n < 2: continue
            ids, cnt = pre[P].unique(return_counts=True); q = int(ids[cnt.argmax()])
            Q = pre == q; s0, hi0, _ = two_means(vote[Q], pix[Q])
            small = hi0 if hi0.sum() <= (~hi0).sum() else ~hi0
            su = sure[Q]; cq = car[Q]
            fired = s0 >= G["split_separation"] and int((hi0 & su).sum()) >= G["min_area"] and int((~hi0 & su).sum()) >= G["min_area"]
            merged.append((tree, s0, fired, int(small.sum()), int((small & cq).sum()), st))
            print(f"tree {tree} {key:27s} P{i} ({int(P.sum())} px, {n} cars) from nearest-centre instance {q} ({int(Q.sum())} px): "
                  f"2-means stat {s0:5.2f}, smaller side {int(small.sum())} px ({int((small & su).sum())} sure, {int((small & cq).sum())} on cars), "
                  f"split fired {fired}; stat on P itself {st:.2f}")
print("\n== merged proposals:", len(merged))
hi4 = [m for m in merged if m[1] >= 4]
print(f"  nearest-centre instance's stat >= 4: {len(hi4)}; of those the split fired {sum(m[2] for m in hi4)}; smaller side on cars "
      f"(> 25 % of its px) {sum(m[4] > 0.25 * m[3] for m in hi4)}; smaller side px median {sorted(m[3] for m in hi4)[len(hi4) // 2] if hi4 else 0}")
t = torch.tensor([m[5] for m in merged])
print(f"  stat on the merged proposal itself: max {float(t.max()):.2f}, median {float(t.median()):.2f}, >= 4: {int((t >= 4).sum())}, >= 3: {int((t >= 3).sum())}")
print("\n== every final proposal, 2-means stat by cars held (quartiles)")
for n, name in ((0, "0 cars"), (1, "1 car"), (2, "2+ cars")):
    x = torch.tensor([r[1] for r in allrows if (r[0] >= 2 if n == 2 else r[0] == n)])
    q = torch.quantile(x, torch.tensor([0.25, 0.5, 0.75, 0.9])).tolist()
    print(f"  {name:8s} {len(x):4d} proposals: q25 {q[0]:.2f} median {q[1]:.2f} q75 {q[2]:.2f} q90 {q[3]:.2f}")
print("\n== a second split round at threshold T (and vote-gap / pixel-gap ratio >= R, each side >= 16 px): proposals it would cut")
print("  T    R   | 1-car proposals cut | 2+-car proposals cut | no-car")
for T in (2.5, 3.0, 3.5, 4.0):
    for R in (0.0, 0.5, 0.7):
        sel = [r for r in allrows if r[1] >= T and r[2] >= R and r[3] >= 16]
        print(f"  {T:.1f} {R:.1f}  | {sum(r[0] == 1 for r in sel):19d} | {sum(r[0] >= 2 for r in sel):20d} | {sum(r[0] == 0 for r in sel)}")
