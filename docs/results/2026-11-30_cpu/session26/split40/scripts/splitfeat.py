"""splitfeat.py RAW.pt...: every 2-means split main's grouping makes on frag40's raw outputs (312x96, w0), with
features and a label from the ground-truth instance map (oracle, used only to score). Run from the worktree root:
OUT=feat.json PYTHONPATH=src python $D/scripts/splitfeat.py /tmp/s26data/frag40/raw/raw*.pt (D: this folder)

The instances are main's (split and part separation off; min_area on), the split is _split_parts itself on them.
Label per split: 'one car' when both parts' majority true car (>= 50 % of the part) is the same car, 'two cars' when
they are two different cars, else 'other'. Features: area (pixels), sep (the split's separation in pooled std),
gap (px between the parts' vote means), gap / sqrt(area), conv (the parts' vote-mean distance over their pixel-mean
distance: one car's offsets converge on one centre, so its halves' votes lie closer than its halves do)."""
import json
import os
import sys

import torch

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic import panoptic
from sdn3d.semantic.predict import GROUPING_DEFAULTS

G = GROUPING_DEFAULTS


def splits(fr: dict, things: list[int]) -> list[dict]:
    prob = fr["logits"].float().softmax(0)[None]
    label = prob.argmax(1)
    inst, _ = panoptic.group_vehicles(label, prob, fr["center"][None], fr["offset"][None], things,
                                      thing_odds=G["thing_odds"], threshold=G["center_threshold"],
                                      nms_kernel=G["nms_kernel"], top_k=G["top_k"], min_area=G["min_area"],
                                      split_separation=None, part_separation=None)
    inst = inst[0]
    v, u = torch.nonzero(inst > 0, as_tuple=True)
    ids, slot = inst[v, u].unique(return_inverse=True)
    off = fr["offset"]
    target = torch.stack([u.float() + off[0, v, u], v.float() + off[1, v, u]], -1)
    sure = torch.isin(label[0, v, u], torch.tensor(things))
    high = panoptic._split_parts(target, slot, len(ids), G["min_area"], G["split_separation"], sure)
    # the separation of every slot, split or not: rerun with a tiny threshold
    anyhigh = panoptic._split_parts(target, slot, len(ids), G["min_area"], 1e-6, sure)
    gi = fr["gt_instances"][v, u]
    pix = torch.stack([u.float(), v.float()], -1)
    heat = fr["center"][0].float()
    peak = (heat == torch.nn.functional.max_pool2d(heat[None, None], 3, 1, 1)[0, 0])[v, u]  # 3x3 local maxima
    hv = heat[v, u]
    out = []
    for j in range(len(ids)):
        m = slot == j
        hi, lo = m & anyhigh, m & ~anyhigh
        if hi.sum() < 1 or lo.sum() < 1:
            continue
        did = bool((m & high).any())
        tv = [target[p].mean(0) for p in (hi, lo)]
        pv = [pix[p].mean(0) for p in (hi, lo)]
        s = target[m] - target[m].mean(0)
        cov = s.T @ s / m.sum()
        ax = torch.linalg.eigh(cov).eigenvectors[:, -1]
        pr = [target[p] @ ax for p in (hi, lo)]
        spread = ((pr[0].var(unbiased=False) + pr[1].var(unbiased=False)) / 2).sqrt().clamp_min(0.5)
        sep = float((pr[0].mean() - pr[1].mean()).abs() / spread)
        maj = []
        for p in (hi, lo):
            g = gi[p]
            car = g[(g >= INSTANCE_DIVISOR) & torch.isin(g // INSTANCE_DIVISOR, torch.tensor(things))]
            if car.numel() == 0:
                maj.append(None)
                continue
            val, cnt = car.unique(return_counts=True)
            maj.append(int(val[cnt.argmax()]) if cnt.max() >= 0.5 * p.sum() else None)
        kind = ("one car" if maj[0] is not None and maj[0] == maj[1] else
                "two cars" if None not in maj else "other")
        area = int(m.sum())
        gap = float((tv[0] - tv[1]).norm())
        box = [(pix[p].amin(0), pix[p].amax(0)) for p in (hi, lo)]
        inbox = [bool(((tv[i] >= box[i][0] - 0.5) & (tv[i] <= box[i][1] + 0.5)).all()) for i in range(2)]
        # pull: how far each part's votes lean from its pixels towards the other part, over the parts' pixel gap
        # (one car: its halves' votes lean towards the car's centre, beyond the cut; a hidden car's point at itself)
        dv = pv[1] - pv[0]
        dd = max(float(dv.norm()), 1e-6)
        pull = [float((tv[0] - pv[0]) @ dv) / dd ** 2, float((tv[1] - pv[1]) @ -dv) / dd ** 2]
        # the centre heatmap on each part: its highest value, its highest 3x3 local maximum, at its votes' mean
        hmax = [float(hv[p].max()) for p in (hi, lo)]
        hpeak = [float((hv * peak)[p].max()) for p in (hi, lo)]
        hvote = [float(heat[int(tv[i][1].round().clamp(0, heat.shape[0] - 1)),
                             int(tv[i][0].round().clamp(0, heat.shape[1] - 1))]) for i in range(2)]
        out.append({"split": did, "pull": pull, "hmax": hmax, "hpeak": hpeak, "hvote": hvote,
                    "kind": kind, "area": area, "sep": sep, "gap": gap, "gap_rel": gap / area ** 0.5,
                    "conv": gap / max(float((pv[0] - pv[1]).norm()), 1e-6), "inbox": inbox,
                    "n": [int(hi.sum()), int(lo.sum())]})
    return out


if __name__ == "__main__":
    rows = []
    for path in sys.argv[1:]:
        raw = torch.load(path, weights_only=False)
        for key, fr in raw["frames"].items():
            for r in splits(fr, raw["things"]):
                rows.append({"raw": os.path.basename(path), "key": key, **r})
    with open(os.environ["OUT"], "w") as f:  # OUT: where the rows go (JSON)
        json.dump(rows, f)
