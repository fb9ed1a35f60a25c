"""diag_pose.py DIAG.json POSE_TABLE_ARGS...: benchmarks/pose_table.py (of the code on the path, run from its tree)
with spies on the test-time fit, recording for every fitted object what decided its end: the fine stage's
hypotheses (loss, fitted yaw, the belief fit._choose saw), the winner, and the appearance the belief was built from
(the lamps' reading, the headlights' reading, the ray, the MultiBin bins). Each record is keyed by the pose
table's row, frame and the object's final yaw (rounded as pose_table writes it), so that score.py can join it to
the pose table's per-object rows. Session 24 (predflip) adds, per object, its mask against the ground truth (an
oracle, read only to score): ``gt_id`` the true car it overlaps most by IoU, ``iou`` that IoU, ``cover`` the share of
that car's true visible pixels the mask holds, ``merged`` the share of the mask on other true vehicles, ``stray`` the
share on no vehicle, and the box ``mask_box`` (l, t, r, b). Run as pose.sh does (PYTHONPATH=CODE/src:CODE, cd
CODE)."""
# ruff: noqa: E402
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import pose_table as pt

import sdn3d.box_objects as bo
import sdn3d.geometric.fit as gf
import sdn3d.proposal_fit as pf

STASH: dict = {"app": [], "choose": [], "masks": [], "eff": [], "rec": []}
OUT: list[dict] = []
CUR = {"key": None}
_choose, _fit_to_masks, _yaw_belief, _derender, _load = gf._choose, gf.fit_to_masks, bo.yaw_belief, pt.derender, \
    pt.load_frame
_choose_again = gf.choose_again


def spy_choose(loss, belief, ry, settings):
    index = _choose(loss, belief, ry, settings)
    STASH["choose"].append((loss.clone(), belief.clone(), ry.clone(), index.clone()))
    return index


def spy_fit(masks, *a, **k):
    STASH["masks"].append(masks.bool().clone())
    ignore = k.get("ignore")
    STASH["eff"].append(masks.bool() & ~ignore.bool() if ignore is not None else masks.bool().clone())
    CUR["in_fit"] = True
    try:
        result = _fit_to_masks(masks, *a, **k)
        STASH["rec"].append(STASH["choose"][-1])  # session 26: the fit's last choice is its record (scene axis: 4)
        return result
    finally:
        CUR["in_fit"] = False


def spy_choose_again(choice, *a, **k):
    """Session 25: main's choose_again (session 24 rechoose) chooses some proposals again without fitting: it is
    recorded as one more fit call of those rows (their input masks found through the fitted masks of the last fit).
    fit_to_masks itself chooses through choose_again: those calls are its own (recorded by spy_fit)."""
    if CUR.get("in_fit"):
        return _choose_again(choice, *a, **k)
    eff, full = STASH["eff"][-1], STASH["masks"][-1]
    rows = [int((eff == m[None]).flatten(1).all(1).nonzero().flatten()[0]) for m in choice.masks]
    STASH["masks"].append(full[rows].clone())
    STASH["eff"].append(eff[rows].clone())
    result = _choose_again(choice, *a, **k)
    STASH["rec"].append(STASH["choose"][-1])
    return result


def spy_belief(appearance, rows):
    STASH["app"].append(None if appearance is None else appearance.rows(rows))
    return _yaw_belief(appearance, rows)


def spy_load(record, *a, **k):
    CUR["key"] = record.key
    return _load(record, *a, **k)


def mask_quality(mask, gt) -> dict:
    """The mask ``(H, W)`` against the true instance map (module doc)."""
    inst = gt.instances
    vehicle = (inst // 1000 == 12) | (inst // 1000 == 13)
    ids = [int(i) for i in inst[mask & vehicle].unique().tolist()]
    n = int(mask.sum())
    rows = mask.any(1).nonzero().flatten()
    cols = mask.any(0).nonzero().flatten()
    box = [int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max())] if n else None
    if not ids:
        return {"gt_id": None, "iou": 0.0, "cover": 0.0, "merged": 0.0, "stray": 1.0, "mask_box": box}
    best, best_iou = None, -1.0
    for i in ids:
        t = inst == i
        iou = int((t & mask).sum()) / int((t | mask).sum())
        if iou > best_iou:
            best, best_iou = i, iou
    t = inst == best
    return {"gt_id": best, "iou": round(best_iou, 4), "cover": round(int((t & mask).sum()) / int(t.sum()), 4),
            "merged": round(int((mask & vehicle & ~t).sum()) / n, 4), "stray": round(int((mask & ~vehicle).sum()) / n,
                                                                                         4), "mask_box": box}


def spy_derender(image, intr, models, source, gt, **kw):
    for v in STASH.values():
        v.clear()
    scene = _derender(image, intr, models, source, gt, **kw)
    row = {"gt": "gt_branch", "boxes": "gt_fit"}.get(source, "pred_fit" if kw.get("fit") is not None else "pred_branch")
    if not STASH["choose"]:
        return scene
    apps = [a for a in STASH["app"] if a is not None]
    o = scene.objects
    done = set()
    # one record per object, from the last fit that fitted its mask (session 24: a proposal may be fitted again)
    for k in reversed(range(len(STASH["masks"]))):
        if len(STASH["rec"]) != len(STASH["masks"]):  # one record per fit (its last choice)
            break
        loss, belief, ry, index = STASH["rec"][k]
        masks = STASH["masks"][k]
        app = apps[k] if len(apps) == len(STASH["masks"]) and len(apps[k].has) == len(masks) else None
        for r in range(len(o.ry)):
            same = (masks == o.mask[r].bool()[None]).flatten(1).all(1).nonzero().flatten()
            if len(same) != 1 or r in done:
                continue
            done.add(r)
            i = int(same[0])
            rec = {"row": row, "frame": CUR["key"], "ry": round(float(o.ry[r]), 4), "loss": loss[i].tolist(),
                   "belief": belief[i].tolist(), "hyp_ry": ry[i].tolist(), "winner": int(index[i]), "fit_call": k}
            if gt is not None and gt.instances is not None:
                rec.update(mask_quality(o.mask[r].bool(), gt))
            if app is not None:
                rec["has"] = bool(app.has[i])
                rec["cue"] = app.cue.__dict__
                rec["app"] = {n: (v[i].tolist() if v[i].dim() else float(v[i]) if v[i].is_floating_point() else
                                  int(v[i])) for n, v in app.values.items()}
            OUT.append(rec)
    return scene


gf._choose, gf.fit_to_masks, bo.yaw_belief, pf.yaw_belief = spy_choose, spy_fit, spy_belief, spy_belief
gf.choose_again = spy_choose_again
pt.derender, pt.load_frame = spy_derender, spy_load
diag = sys.argv[1]
pt.main(sys.argv[2:])
Path(diag).write_text(json.dumps(OUT))
print(f"diag: {len(OUT)} fitted objects -> {diag}", file=sys.stderr)
