# ruff: noqa: E501, E701, E702
"""merged.py RAW.pt... : proposals that hold two or more ground-truth cars (the ground truth is an oracle, used for
scoring only) and why the grouping did not part them. Run from the worktree root with PYTHONPATH=src:. on raw.py's
files (session 21 hidden's raw.py: a Table 1 tree's source frames at 312x96, this session's demo weights).

The grouping is the installed sdn3d.semantic.panoptic.group_vehicles with GROUPING_DEFAULTS and GROUPING='{json}'
overrides (main's grouping on this branch: GROUPING='{"stray_distance": null}'). A proposal P *holds* a car c (Car / Van, at least 16 px) when |P & c| >= HOLD * |c| (default 0.3) and
>= 16 px. A merged proposal holds two or more cars; its cars are ordered by camera distance (gt_range): the nearest is
the occluder, the others hidden; "touching" = the hidden car's mask, grown by one pixel, meets the occluder's.

Per merged (occluder, hidden) pair: the centres above the threshold inside each car's mask; the hidden car's best
heatmap value, and whether it is a local maximum of the NMS window (under the threshold: "peak under threshold"; not a
local maximum of the NMS window: "suppressed"; neither: "no peak"); its pixels' votes (pixel + offset): the share
closer to its own centroid than to the occluder's, and the separation of the two cars' votes along the line between
their means (pooled SDs, what an oracle split could reach); the 2-means split statistic of the instance the nearest-
centre grouping made (the pooled-SD separation _split_parts compares with split_separation). Prints one line a pair and
a summary; JSON=path writes the rows."""
import json
import os
import sys

import torch
import torch.nn.functional as F

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import find_centers, group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

HOLD = float(os.environ.get("HOLD", "0.3"))
G = {**GROUPING_DEFAULTS, **json.loads(os.environ.get("GROUPING", "{}"))}


def group(fr, things, g):
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"],
                          threshold=g["center_threshold"], nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"],
                          split_separation=g["split_separation"], part_separation=g["part_separation"],
                          stray_distance=g.get("stray_distance"), stray_reach=g.get("stray_reach", 0.0))[0][0]


def split_stat(votes):
    """the 2-means separation (pooled SDs) of _split_parts on one instance's votes (N, 2)."""
    d = votes - votes.mean(0)
    cov = d.T @ d / len(d)
    angle = 0.5 * torch.atan2(2 * cov[0, 1], cov[0, 0] - cov[1, 1])
    s = d[:, 0] * angle.cos() + d[:, 1] * angle.sin()
    cut = torch.tensor(0.0)
    for _ in range(16):
        hi = s > cut
        if hi.all() or (~hi).all(): break
        cut = (s[hi].mean() + s[~hi].mean()) / 2
    hi = s > cut
    if hi.all() or (~hi).all(): return 0.0
    r = torch.where(hi, s - s[hi].mean(), s - s[~hi].mean())
    sd = (((r[hi] ** 2).mean() + (r[~hi] ** 2).mean()) / 2).sqrt().clamp_min(0.5)
    return float((s[hi].mean() - s[~hi].mean()) / sd)


def oracle_sep(va, vb):
    """separation of two vote sets along the line between their means (pooled SDs)."""
    ma, mb = va.mean(0), vb.mean(0); axis = (mb - ma) / (mb - ma).norm().clamp_min(1e-6)
    pa, pb = va @ axis, vb @ axis
    return float((pb.mean() - pa.mean()) / ((pa.var(unbiased=False) + pb.var(unbiased=False)) / 2).sqrt().clamp_min(0.5))


def main():
    rows = []
    for path in sys.argv[1:]:
        raw = torch.load(path, weights_only=False); things = raw["things"]; tree = os.path.basename(path)
        for key, fr in raw["frames"].items():
            inst = group(fr, things, G)
            pre = group(fr, things, {**G, "split_separation": None, "part_separation": None, "stray_distance": None})
            gi = fr["gt_instances"]; rng = fr["gt_range"]
            cars = {int(i): gi == i for i in gi.unique().tolist()
                    if i >= INSTANCE_DIVISOR and i // INSTANCE_DIVISOR in things and int((gi == i).sum()) >= 16}
            center = fr["center"][None]; h, w = center.shape[-2:]
            uv, sc, valid = find_centers(center, G["center_threshold"], G["nms_kernel"], G["top_k"])
            cen = uv[0][valid[0]].long()
            peak7 = center == F.max_pool2d(center, G["nms_kernel"], 1, G["nms_kernel"] // 2)
            peak3 = center == F.max_pool2d(center, 3, 1, 1)
            vv, uu = torch.meshgrid(torch.arange(h).float(), torch.arange(w).float(), indexing="ij")
            vote = torch.stack([uu + fr["offset"][0], vv + fr["offset"][1]], -1)  # (H, W, 2)
            for p in inst.unique().tolist():
                if p <= 0: continue
                P = inst == p
                held = [c for c, m in cars.items() if int((P & m).sum()) >= max(16, HOLD * int(m.sum()))]
                if len(held) < 2: continue
                held.sort(key=lambda c: rng.get(c % INSTANCE_DIVISOR, 1e9))
                o = held[0]; O = cars[o]
                for hcar in held[1:]:
                    H = cars[hcar]
                    touch = bool((F.max_pool2d(H[None, None].float(), 3, 1, 1)[0, 0].bool() & O).any())
                    n_cen_o = sum(bool(O[c[1], c[0]]) for c in cen.tolist()); n_cen_h = sum(bool(H[c[1], c[0]]) for c in cen.tolist())
                    hm = center[0, 0].masked_fill(~H, -1)
                    hmax = float(hm.max())
                    loc7 = center[0, 0][H & peak7[0, 0]]; loc3 = center[0, 0][H & peak3[0, 0]]
                    if n_cen_h: why_c = "centre in hidden car"
                    elif loc7.numel() and float(loc7.max()) > 0: why_c = f"peak under threshold ({float(loc7.max()):.3f})"
                    elif loc3.numel() and float(loc3.max()) >= G["center_threshold"]: why_c = f"suppressed by NMS ({float(loc3.max()):.3f})"
                    elif loc3.numel(): why_c = f"local peak {float(loc3.max()):.3f} not a window max"
                    else: why_c = "no peak"
                    ph, po = P & H, P & O
                    co, ch = O.nonzero().float().mean(0).flip(0), H.nonzero().float().mean(0).flip(0)  # (u, v)
                    vh, vo = vote[ph], vote[po]
                    own = float(((vh - ch).norm(dim=-1) < (vh - co).norm(dim=-1)).float().mean())
                    # the nearest-centre instance that holds most of P (before the split and the part rule)
                    ids, cnt = pre[P].unique(return_counts=True)
                    q = int(ids[cnt.argmax()])
                    stat = split_stat(vote[pre == q]) if q > 0 else float("nan")
                    r = {"tree": tree, "key": key, "proposal": p, "occluder": o, "hidden": hcar, "touch": touch,
                         "o_px": int(O.sum()), "h_px": int(H.sum()), "p_px": int(P.sum()), "o_in_p": int(po.sum()), "h_in_p": int(ph.sum()),
                         "o_range": rng.get(o % INSTANCE_DIVISOR), "h_range": rng.get(hcar % INSTANCE_DIVISOR),
                         "centres_o": n_cen_o, "centres_h": n_cen_h, "h_heat_max": hmax, "why_centre": why_c,
                         "h_votes_own": own, "vote_sep_oracle": oracle_sep(vo, vh), "split_stat": stat,
                         "h_vote_to_own": float((vh.mean(0) - ch).norm()), "h_vote_to_occ": float((vh.mean(0) - co).norm())}
                    rows.append(r)
                    print(f"{tree[:10]} {key:28s} P{p} O{o}({r['o_in_p']}/{r['o_px']}px, {r['o_range']:.1f}m) H{hcar}({r['h_in_p']}/{r['h_px']}px, {r['h_range']:.1f}m) "
                          f"touch={int(touch)} cen O/H {n_cen_o}/{n_cen_h} | {why_c} | H votes own {own:.2f}, mean to own {r['h_vote_to_own']:.1f} / occ {r['h_vote_to_occ']:.1f} px "
                          f"| oracle sep {r['vote_sep_oracle']:.2f}, split stat {stat:.2f}")
    n = len(rows); props = {(r["tree"], r["key"], r["proposal"]) for r in rows}
    print(f"\n{len(props)} merged proposals (hold >= {HOLD}), {n} (occluder, hidden) pairs; touching {sum(r['touch'] for r in rows)}")
    for k in ("centre in hidden car", "peak under threshold", "suppressed by NMS", "local peak", "no peak"):
        print(f"  {k}: {sum(r['why_centre'].startswith(k) for r in rows)}")
    print(f"  hidden votes mostly own (>0.5): {sum(r['h_votes_own'] > 0.5 for r in rows)}; split stat >= {G['split_separation']}: {sum(r['split_stat'] >= (G['split_separation'] or 1e9) for r in rows)}; oracle sep >= 3: {sum(r['vote_sep_oracle'] >= 3 for r in rows)}")
    if os.environ.get("JSON"): json.dump(rows, open(os.environ["JSON"], "w"), indent=1)


main()
