# ruff: noqa: E501, E701, E702
"""census.py RAW.pt... : per ground-truth car (Car / Van over the paper's pixel filter at the size; the ground truth is an
oracle used for scoring only) of the frames raw.py saved, the best proposal IoU of the grouping (the installed
sdn3d.semantic's thing_label and group_instances as SemanticPredictor calls them, with GROUPING_DEFAULTS,
GROUPING='{json}' overriding them (main's grouping: GROUPING='{"thing_odds": null, "split_separation": null}'); VARIANT=flip uses the flip-averaged outputs), the failure kind
and where it goes wrong. Prints a table; JSON=path writes every car's row.

Kinds (P = the proposal with the largest intersection with the car):
  fine: best IoU >= 0.5;  none: no proposal covers 20 % of the car;  merged: P lies mostly (> 50 %) outside the car
  (merged_car: most of P's outside pixels are another car; merged_bg: the background); cut: P is mostly the car but
  covers < 50 % of it while another proposal covers >= 20 %; partial: the rest.
Causes (first that applies): semantic: under half the car's pixels are called Car/Van by the semantic map;
  no_centre: no centre inside the car (heat_below: the heatmap's maximum in the car under the threshold;
  suppressed: above it but a stronger peak within the NMS window wins); votes: a centre inside but under half of the
  car's thing pixels voted for it; two_centres: more than one centre inside; other. ("Thing pixels" are those the
  grouping's class map calls Car/Van: with thing_odds, more than the arg-max.)"""
import json
import os
import sys

import torch

from sdn3d.evaluation.proposal_recall import min_pixels_at
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import find_centers, group_instances, thing_label
from sdn3d.semantic.predict import GROUPING_DEFAULTS

VARIANT = os.environ.get("VARIANT", "plain")


def segment(fr, things, g):
    suf = "_flip" if VARIANT == "flip" else ""
    prob = fr["logits" + suf].float().softmax(0)[None]
    label = thing_label(prob, things, g.get("thing_odds"))  # what SemanticPredictor groups (None: the arg-max)
    center, offset = fr["center" + suf][None], fr["offset" + suf][None]
    sure = torch.isin(prob.argmax(1), torch.tensor(things))
    inst, lab = group_instances(label, center, offset, things, threshold=g["center_threshold"], nms_kernel=g["nms_kernel"],
                                top_k=g["top_k"], min_area=g["min_area"], split_separation=g.get("split_separation"), sure=sure)
    return inst[0], lab[0], label[0], center[0, 0], offset[0]


def cars(fr, things, size):
    gi = fr["gt_instances"]; ids = gi.unique()
    ids = ids[(ids >= INSTANCE_DIVISOR) & torch.isin(ids // INSTANCE_DIVISOR, torch.tensor(things))]
    return [(int(i), gi == i) for i in ids if int((gi == i).sum()) > min_pixels_at(*size)]


def rows_of(raw, g=None):
    g = {**GROUPING_DEFAULTS, **json.loads(os.environ.get("GROUPING", "{}"))} if g is None else g
    things, size = raw["things"], raw["size"]
    out = []
    for key, fr in raw["frames"].items():
        inst, lab, label0, center, offset = segment(fr, things, g)
        uv, sc, valid = find_centers(center[None, None], g["center_threshold"], g["nms_kernel"], g["top_k"])
        cen = uv[0][valid[0]].long()
        pids = inst.unique(); pids = pids[pids > 0]
        is_thing = torch.isin(label0, torch.tensor(things))
        gi = fr["gt_instances"]
        for cid, m in cars(fr, things, size):
            area = int(m.sum()); r = {"key": key, "car": cid, "area": area}
            best, inter_max, P = 0.0, 0, None
            covs = []
            for p in pids.tolist():
                pm = inst == p; it = int((pm & m).sum())
                if not it: continue
                iou = it / int((pm | m).sum()); covs.append(it / area)
                if iou > best: best = iou
                if it > inter_max: inter_max, P = it, pm
            r["iou"] = best
            cov = inter_max / area; pur = inter_max / int(P.sum()) if P is not None else 0.0
            if best >= 0.5: kind = "fine"
            elif cov < 0.2: kind = "none"
            elif pur < 0.5:
                outside = P & ~m; other_car = outside & (gi >= INSTANCE_DIVISOR) & torch.isin(gi // INSTANCE_DIVISOR, torch.tensor(things))
                kind = "merged_car" if int(other_car.sum()) * 2 > int(outside.sum()) else "merged_bg"
            elif cov < 0.5 and sum(c >= 0.2 for c in covs) >= 2: kind = "cut"
            else: kind = "partial"
            r["kind"] = kind; r["cover"] = cov; r["purity"] = pur
            sem = float((is_thing & m).sum()) / area; r["sem_thing"] = sem
            inside = [tuple(c) for c in cen.tolist() if bool(m[c[1], c[0]])]
            r["centres_in"] = len(inside); hm = float(center[m].max()); r["heat_max"] = hm
            # votes of the car's thing pixels: share that went to the modal proposal among proposals centred inside
            tp = m & (inst > 0)
            if tp.any():
                v = inst[tp]; mode = torch.mode(v).values; r["modal_share"] = float((v == mode).float().mean())
            if kind == "fine": cause = "-"
            elif sem < 0.5: cause = "semantic"
            elif not inside: cause = "heat_below" if hm <= g["center_threshold"] else "suppressed"
            elif len(inside) >= 2: cause = "two_centres"
            else:
                # the car's thing pixels voting for the proposal of its one inside centre
                c = inside[0]; pid = int(inst[c[1], c[0]])
                share = float(((inst == pid) & m & is_thing).sum()) / max(float((m & is_thing).sum()), 1)
                r["own_share"] = share
                cause = "votes" if share < 0.5 else "other"
            r["cause"] = cause
            out.append(r)
    return out


def table(rows, title):
    n = len(rows); k = {}
    for r in rows: k.setdefault((r["kind"], r["cause"]), 0); k[(r["kind"], r["cause"])] += 1
    r5 = sum(r["iou"] >= 0.5 for r in rows); r3 = sum(r["iou"] >= 0.3 for r in rows)
    print(f"## {title}: {n} cars; best IoU >= 0.5: {r5} ({r5 / max(n, 1):.3f}); >= 0.3: {r3} ({r3 / max(n, 1):.3f})")
    for kind in ("fine", "none", "merged_car", "merged_bg", "cut", "partial"):
        sub = {c: v for (kk, c), v in k.items() if kk == kind}
        if sub: print(f"  {kind:10s} {sum(sub.values()):4d}  " + ", ".join(f"{c} {v}" for c, v in sorted(sub.items(), key=lambda x: -x[1])))


if __name__ == "__main__":
    allrows = []
    for path in sys.argv[1:]:
        raw = torch.load(path, weights_only=False)
        rows = rows_of(raw)
        for r in rows: r["raw"] = os.path.basename(path)
        table(rows, f"{os.path.basename(path)} ({VARIANT})"); allrows += rows
    if len(sys.argv) > 2: table(allrows, f"pooled ({VARIANT})")
    if os.environ.get("JSON"):
        with open(os.environ["JSON"], "w") as f: json.dump(allrows, f, indent=0)
