"""diag_pose.py DIAG.json POSE_TABLE_ARGS...: benchmarks/pose_table.py (of the code on the path, run from its tree)
with spies on the test-time fit, recording for every fitted object what decided its end: the fine stage's
hypotheses (loss, fitted yaw, the belief fit._choose saw), the winner, and the appearance the belief was built from
(the lamps' reading, the headlights' reading, the ray, the MultiBin bins). Each record is keyed by the pose
table's row, frame and the object's final yaw (rounded as pose_table writes it), so that score.py can join it to
the pose table's per-object rows. Run as pose.sh does (PYTHONPATH=CODE/src:CODE, cd CODE)."""
# ruff: noqa: E402
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import pose_table as pt

import sdn3d.box_objects as bo
import sdn3d.geometric.fit as gf
import sdn3d.proposal_fit as pf

STASH: dict = {"app": [], "choose": [], "masks": []}
OUT: list[dict] = []
CUR = {"key": None}
_choose, _fit_to_masks, _yaw_belief, _derender, _load = gf._choose, gf.fit_to_masks, bo.yaw_belief, pt.derender, \
    pt.load_frame


def spy_choose(loss, belief, ry, settings):
    index = _choose(loss, belief, ry, settings)
    STASH["choose"].append((loss.clone(), belief.clone(), ry.clone(), index.clone()))
    return index


def spy_fit(masks, *a, **k):
    STASH["masks"].append(masks.bool().clone())
    return _fit_to_masks(masks, *a, **k)


def spy_belief(appearance, rows):
    STASH["app"].append(None if appearance is None else appearance.rows(rows))
    return _yaw_belief(appearance, rows)


def spy_load(record, *a, **k):
    CUR["key"] = record.key
    return _load(record, *a, **k)


def spy_derender(image, intr, models, source, gt, **kw):
    for v in STASH.values():
        v.clear()
    scene = _derender(image, intr, models, source, gt, **kw)
    row = {"gt": "gt_branch", "boxes": "gt_fit"}.get(source, "pred_fit" if kw.get("fit") is not None else "pred_branch")
    if not STASH["choose"] or len(STASH["masks"]) != 1:
        return scene
    loss, belief, ry, index = STASH["choose"][-1]
    masks = STASH["masks"][0]
    apps = [a for a in STASH["app"] if a is not None]
    app = None
    if len(apps) == 1 and len(apps[0].has) == len(masks):
        app = apps[0]
    o = scene.objects
    for r in range(len(o.ry)):
        same = (masks == o.mask[r].bool()[None]).flatten(1).all(1).nonzero().flatten()
        if len(same) != 1:
            continue
        i = int(same[0])
        rec = {"row": row, "frame": CUR["key"], "ry": round(float(o.ry[r]), 4), "loss": loss[i].tolist(),
               "belief": belief[i].tolist(), "hyp_ry": ry[i].tolist(), "winner": int(index[i])}
        if app is not None:
            rec["has"] = bool(app.has[i])
            rec["cue"] = app.cue.__dict__
            rec["app"] = {k: (v[i].tolist() if v[i].dim() else float(v[i]) if v[i].is_floating_point() else
                              int(v[i])) for k, v in app.values.items()}
        OUT.append(rec)
    return scene


gf._choose, gf.fit_to_masks, bo.yaw_belief, pf.yaw_belief = spy_choose, spy_fit, spy_belief, spy_belief
pt.derender, pt.load_frame = spy_derender, spy_load
diag = sys.argv[1]
pt.main(sys.argv[2:])
Path(diag).write_text(json.dumps(OUT))
print(f"diag: {len(OUT)} fitted objects -> {diag}", file=sys.stderr)
