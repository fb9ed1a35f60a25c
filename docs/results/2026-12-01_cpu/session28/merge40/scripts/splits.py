"""splits.py RAW.pt...: per true car (Car / Van instances of the tree's ground-truth instance map over the paper's
pixel filter at 312x96, 64 px: an oracle, used only to score) of the frames raw.py saved, the proposals the grouping
makes on it and which rule made each split. Grouping: the code on PYTHONPATH (group_vehicles with its
GROUPING_DEFAULTS; GROUPING='{json}' overrides them, e.g. '{"nms_kernel": 11}'; main's grouping on this branch:
GROUPING='{"merge_reach": null}').

A proposal covers a car when >= 10 % of the proposal's pixels lie on it or it holds >= 5 % of the car. A car covered
by two or more proposals is *split* when an extra proposal (all but the one with most pixels on the car) lies for at
least half its own pixels on the car (a *fragment*; the other extra proposals are neighbours' spills); each fragment
is blamed on
the rule its id names (group_instances' ids: k <= K a heatmap centre, K < k <= 2K the second part of the 2-means
split, k > 2K a part that left its instance by part separation; K = top_k): 'two peaks' (a centre proposal: the
heatmap has another peak for the car that NMS kept), '2-means split' (the second part, or the first part when the
second is the car's main proposal), 'part separation'. 'lost' = the car's pixels in no proposal (thing_label called
them stuff, or their instance fell under min_area). A *merge*: a proposal holding >= 25 % of each of two true cars
(counted once per extra car). Also recall (best IoU >= 0.5) and panoptic quality of the Car / Van things
(semantic/pq.py's matching: IoU > 0.5). Prints a markdown table per file and pooled; JSON=path writes every car."""
import json
import os
import sys

import torch

from sdn3d.evaluation.proposal_recall import min_pixels_at
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

G = {**GROUPING_DEFAULTS, **json.loads(os.environ.get("GROUPING", "{}"))}


def group(fr: dict, things: list[int]) -> torch.Tensor:
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things,
                          thing_odds=G["thing_odds"], threshold=G["center_threshold"], nms_kernel=G["nms_kernel"],
                          top_k=G["top_k"], min_area=G["min_area"], split_separation=G["split_separation"],
                          part_separation=G["part_separation"],
                          **{k: G[k] for k in ("merge_reach", "merge_separation") if k in G})[0][0]


def rule(k: int, top_k: int) -> str:
    return "two peaks" if k <= top_k else "2-means split" if k <= 2 * top_k else "part separation"


def census(raw: dict) -> list[dict]:
    things, (w, h) = raw["things"], raw["size"]
    rows = []
    for key, fr in raw["frames"].items():
        inst = group(fr, things)
        gi = fr["gt_instances"]
        ids = [int(i) for i in gi.unique() if i >= INSTANCE_DIVISOR and int(i) // INSTANCE_DIVISOR in things]
        cars = {i: gi == i for i in ids if int((gi == i).sum()) > min_pixels_at(w, h)}
        pids = [int(p) for p in inst.unique() if p > 0]
        pm = {p: inst == p for p in pids}
        parea = {p: int(m.sum()) for p, m in pm.items()}
        for cid, m in cars.items():
            area = int(m.sum())
            on = {p: int((pm[p] & m).sum()) for p in pids}
            cover = sorted((p for p in pids if on[p] and (on[p] >= 0.1 * parea[p] or on[p] >= 0.05 * area)),
                           key=lambda p: -on[p])
            best = max((on[p] / int((pm[p] | m).sum()) for p in pids if on[p]), default=0.0)
            causes = []
            kk = {p % INSTANCE_DIVISOR for p in cover}
            # a fragment: an extra proposal lying for >= half its pixels on this car (not a neighbour's spill)
            frags = [p for p in cover[1:] if on[p] >= 0.5 * parea[p]]
            for p in frags:
                k = p % INSTANCE_DIVISOR
                c = rule(k, G["top_k"])
                if c == "two peaks" and k + G["top_k"] in kk:
                    c = "2-means split"  # the first part of a split whose second part is the car's main proposal
                causes.append(c)
            merged = sum(1 for p in cover if on[p] >= 0.25 * area and any(
                int((pm[p] & o).sum()) >= 0.25 * int(o.sum()) for j, o in cars.items() if j != cid))
            rows.append({"key": key, "car": cid, "area": area, "proposals": len(cover), "fragments": len(frags),
                         "causes": causes, "spill": len(cover) - 1 - len(frags),
                         "lost": area - sum(on.values()), "iou": best, "merged": merged,
                         "split_px": sum(on[p] for p in frags)})
    return rows


def pq(raw: dict) -> tuple[float, int, int, int]:
    """Car / Van panoptic quality over the frames: IoU > 0.5 matches, (sum IoU / (TP + FP / 2 + FN / 2)); cars under
    the pixel filter and proposals matched to none are both counted (PQ's usual rule)."""
    things = raw["things"]
    s, tp, fp, fn = 0.0, 0, 0, 0
    for fr in raw["frames"].values():
        inst, gi = group(fr, things), fr["gt_instances"]
        gids = [int(i) for i in gi.unique() if i >= INSTANCE_DIVISOR and int(i) // INSTANCE_DIVISOR in things]
        pids = [int(p) for p in inst.unique() if p > 0]
        matched = set()
        for g in gids:
            gm = gi == g
            for p in pids:
                it = int(((inst == p) & gm).sum())
                if it and it / int(((inst == p) | gm).sum()) > 0.5:
                    s += it / int(((inst == p) | gm).sum())
                    tp += 1
                    matched.add(p)
                    break
            else:
                fn += 1
        fp += len([p for p in pids if p not in matched])
    return s / max(tp + fp / 2 + fn / 2, 1e-9), tp, fp, fn


def summary(rows: list[dict], q: tuple[float, int, int, int], title: str) -> str:
    n = len(rows)
    split = [r for r in rows if r["fragments"] >= 1]
    causes: dict[str, int] = {}
    for r in rows:
        for c in r["causes"]:
            causes[c] = causes.get(c, 0) + 1
    big = [r for r in rows if r["area"] >= 1500]
    return (f"| {title} | {n} | {sum(r['iou'] >= 0.5 for r in rows)} | {q[0]:.3f} ({q[1]}/{q[2]}/{q[3]}) | "
            f"{len(split)} | {sum(r['fragments'] for r in split)} | {sum(r['spill'] for r in rows)} | "
            + " / ".join(str(causes.get(c, 0)) for c in ("two peaks", "2-means split", "part separation"))
            + f" | {sum(r['split_px'] for r in rows)} | {sum(r['lost'] for r in rows)} | "
            f"{sum(r['merged'] for r in rows)} | {sum(r['fragments'] >= 1 for r in big)}/{len(big)} |")


if __name__ == "__main__":
    print(f"grouping: {json.dumps(G)}\n")
    print("| tree | true cars | found (IoU >= 0.5) | PQ Car/Van (TP/FP/FN) | split cars | fragments | "
          "neighbours' spills | fragments by two peaks / 2-means split / part separation | px in fragments | "
          "px lost (no proposal) | "
          "merges | big cars (>= 1500 px) split |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    allrows, tot = [], [0.0, 0, 0, 0]
    for path in sys.argv[1:]:
        raw = torch.load(path, weights_only=False)
        rows, q = census(raw), pq(raw)
        for r in rows:
            r["raw"] = os.path.basename(path)
        print(summary(rows, q, os.path.basename(path)))
        allrows += rows
        tot = [tot[0] + q[0] * (q[1] + q[2] / 2 + q[3] / 2), tot[1] + q[1], tot[2] + q[2], tot[3] + q[3]]
    denom = tot[1] + tot[2] / 2 + tot[3] / 2
    print(summary(allrows, (tot[0] / max(denom, 1e-9), tot[1], tot[2], tot[3]), "pooled"))
    if os.environ.get("JSON"):
        with open(os.environ["JSON"], "w") as f:
            json.dump(allrows, f, indent=0)
