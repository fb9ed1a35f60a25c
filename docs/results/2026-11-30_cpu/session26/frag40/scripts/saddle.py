"""saddle.py RAW.pt...: the heatmap between pairs of kept centres (main's find_centers, GROUPING_DEFAULTS) whose
proposals touch (8-neighbours): per pair, whether both lie on one true car (a fragment pair: ground truth, an oracle
used only to diagnose) or on two, the centres' distance, peaks and the saddle ratio (the heatmap's minimum on the
segment between them over the lower peak), the vote separation (votes' means apart over their pooled spread on the
line through both, as the join computes it) and whether the smaller one's votes land in the bigger one's box. Prints
a line per pair and histograms of the ratio and the separation for both kinds."""
import sys

import torch
import torch.nn.functional as F

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import find_centers, group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

G = {**GROUPING_DEFAULTS, "merge_reach": None}  # main's grouping (the pairs the join decides on)
stats: dict[str, list[float]] = {"same car": [], "two cars": []}
sep_stats: dict[str, list[float]] = {"same car": [], "two cars": []}
for path in sys.argv[1:]:
    raw = torch.load(path, weights_only=False)
    things = raw["things"]
    for key, fr in raw["frames"].items():
        prob = fr["logits"].float().softmax(0)[None]
        center = fr["center"][None]
        inst = group_vehicles(prob.argmax(1), prob, center, fr["offset"][None], things, thing_odds=G["thing_odds"],
                              threshold=G["center_threshold"], nms_kernel=G["nms_kernel"], top_k=G["top_k"],
                              min_area=G["min_area"], split_separation=G["split_separation"],
                              part_separation=G["part_separation"], merge_reach=None)[0][0]
        uv, sc, valid = find_centers(center, G["center_threshold"], G["nms_kernel"], G["top_k"])
        uv, sc = uv[0][valid[0]], sc[0][valid[0]]
        gi = fr["gt_instances"]
        heat = center[0, 0]
        for i in range(len(uv)):
            for j in range(i + 1, len(uv)):
                pi, pj = i + 1, j + 1  # proposal k of centre rank
                mi = (inst % INSTANCE_DIVISOR == pi) & (inst > 0)
                mj = (inst % INSTANCE_DIVISOR == pj) & (inst > 0)
                if not mi.any() or not mj.any():
                    continue
                grown = F.max_pool2d(mi[None, None].float(), 3, 1, 1)[0, 0] > 0
                if not (grown & mj).any():
                    continue
                gi_i, gi_j = gi[mi], gi[mj]
                ci, cj = int(torch.mode(gi_i).values), int(torch.mode(gi_j).values)
                if ci < INSTANCE_DIVISOR or cj < INSTANCE_DIVISOR:
                    continue
                t = torch.linspace(0, 1, 41)
                seg = uv[i][None] + t[:, None] * (uv[j] - uv[i])[None]
                vals = heat[seg[:, 1].round().long(), seg[:, 0].round().long()]
                ratio = float(vals.min() / min(sc[i], sc[j]))
                off = fr["offset"]
                vv, uu = torch.meshgrid(torch.arange(heat.shape[0]), torch.arange(heat.shape[1]), indexing="ij")
                vote = torch.stack([uu + off[0], vv + off[1]], -1)  # (H, W, 2)
                a, b = vote[mi], vote[mj]
                axis = (b.mean(0) - a.mean(0))
                gap = float(axis.norm())
                axis = axis / axis.norm().clamp_min(1e-6)
                pa, pb = a @ axis, b @ axis
                sep = gap / float(((pa.var() + pb.var()) / 2).sqrt().clamp_min(0.5))
                sep_stats["same car" if ci == cj else "two cars"].append(sep)
                small, big = (mi, mj) if int(mi.sum()) < int(mj.sum()) else (mj, mi)
                vm = vote[small].mean(0).round().long()
                vb = vote[big].mean(0).round().long()
                ys, xs = torch.nonzero(big, as_tuple=True)
                inbox = bool(xs.min() <= vm[0] <= xs.max() and ys.min() <= vm[1] <= ys.max())
                ys2, xs2 = torch.nonzero(small, as_tuple=True)
                bigin = bool(xs2.min() <= vb[0] <= xs2.max() and ys2.min() <= vb[1] <= ys2.max())
                small_own = bool(xs2.min() <= vm[0] <= xs2.max() and ys2.min() <= vm[1] <= ys2.max())
                kind = "same car" if ci == cj else "two cars"
                stats[kind].append(ratio)
                print(f"{path[-6:-3]} {key} {kind}: d {float((uv[i] - uv[j]).norm()):.1f} peaks {float(sc[i]):.2f}"
                      f"/{float(sc[j]):.2f} saddle ratio {ratio:.2f} areas {int(mi.sum())}/{int(mj.sum())} "
                      f"vote sep {sep:.2f} "
                      f"small_votes_in_big_box {int(inbox)} small_votes_in_own_box {int(small_own)} "
                      f"big_votes_in_small_box {int(bigin)}")
for kind, r in stats.items():
    r = torch.tensor(r)
    hist = [int(((r >= a) & (r < a + 0.1)).sum()) for a in torch.arange(0, 1.0, 0.1).tolist()]
    print(kind, len(r), "ratio histogram [0,0.1)...[0.9,1]:", hist)
for kind, r in sep_stats.items():
    r = torch.tensor(r)
    hist = [int(((r >= a) & (r < a + 0.5)).sum()) for a in torch.arange(0, 6.0, 0.5).tolist()] + [int((r >= 6).sum())]
    print(kind, len(r), "vote separation histogram [0,0.5)...[5.5,6), >=6:", hist)
