# ruff: noqa: B905, E401, E402, E501, E701, E702, F401, F841, I001
"""cutcars.py TREE W OUT [W H]: per car of a (tuning) tree, row gt_fit (ground-truth masks + boxes), the truth, the
fit, and what the appearance read (lamps, border side, bins' belief) at the truth's yaw and its reverse."""
import sys, math, json, torch, numpy as np
import sdn3d.derender as D
from sdn3d.models import Models
from sdn3d.geometric.lamps import LampCue, evidence_of
from sdn3d.geometric.model import yaw_distribution
sys.path.insert(0, "/work/main/benchmarks")
import pose_table

import os
if os.environ.get("VARIANT") == "cutnet0":
    import sdn3d.geometric.facing as F
    _fb = F.facing_belief
    def fb(appearance, cue=None, bins=True):
        score = _fb(appearance, cue, bins)
        if "border_side" not in appearance:
            return score
        cut = appearance["border_side"] != 0
        no_net = _fb({k: v for k, v in appearance.items()}, cue, bins)
        def s2(ry):
            full = score(ry)
            a = {k: appearance[k] for k in F.APPEARANCE_KEYS}
            from sdn3d.geometric.lamps import evidence_of
            front = (appearance["front_present"].bool(), appearance["front_usable"].bool(), appearance["front_offset"]) if all(k in appearance for k in F.FRONT_KEYS) else None
            lamps = evidence_of(a["lamp_present"].bool(), a["lamp_usable"].bool(), a["lamp_offset"], ry.to(a["net_ry"].dtype) - a["ray"][:, None], cue or F.LampCue(), front=front, border=appearance["border_side"])
            return torch.where(cut[:, None], lamps, full)
        return s2
    F.facing_belief = fb
if os.environ.get("LAMP_TOP"):
    from dataclasses import replace as _rp
    import sdn3d.models as _M
    _fc = _M.Models.from_checkpoints.__func__
    def _fc2(cls, *a, **k):
        m = _fc(cls, *a, **k)
        if m.geometric is not None and m.geometric.lamp_cue is not None:
            m.geometric.lamp_cue = _rp(m.geometric.lamp_cue, lamp_top=float(os.environ["LAMP_TOP"]))
        return m
    _M.Models.from_checkpoints = classmethod(_fc2)
tree, w, out = sys.argv[1], sys.argv[2], sys.argv[3]
size = sys.argv[4:6]
captured = []
orig = D._predict_geometry
def wrapped(*a, **k):
    r = orig(*a, **k)
    captured.append({kk: v.detach().cpu().clone() for kk, v in r.items() if torch.is_tensor(v)})
    return r
D._predict_geometry = wrapped
res = pose_table.main(["--geometric", f"{w}/geometric/checkpoints/inference.pt", "--semantic", f"{w}/semantic/checkpoints/inference.pt",
                       "--data-root", tree, "--part", "all", "--max-frames", "40", "--threads", "1", "--rows", "gt_fit",
                       *(["--image-size", *size] if size else [])])
rows = res["objects"]["fit, oracle: ground-truth masks + boxes"]
frames = []
for r in rows:
    if not frames or frames[-1][0] != r["frame"]: frames.append((r["frame"], []))
    frames[-1][1].append(r)
cue = LampCue()
outrows = []
assert len(frames) == len(captured), (len(frames), len(captured))
for (key, objs), p in zip(frames, captured):
    if len(p["ry"]) != len(objs):
        print("skip", key, len(p["ry"]), len(objs)); continue
    for j, o in enumerate(objs):
        ray = float(p["ray"][j]); tr = o["true_ry"]
        ryh = torch.tensor([[tr, tr + math.pi]], dtype=torch.float64)
        alpha = ryh - ray
        sl = slice(j, j + 1)
        front = (p["front_present"][sl].bool(), p["front_usable"][sl].bool(), p["front_offset"][sl].double()) if "front_present" in p else None
        lam = evidence_of(p["lamp_present"][sl].bool(), p["lamp_usable"][sl].bool(), p["lamp_offset"][sl].double(), alpha, cue,
                          front=front, border=p["border_side"][sl].double() if "border_side" in p else None)
        raw = {k: p[k][sl].double() for k in ("yaw_bins", "yaw_residual", "yaw_ray")} if "yaw_bins" in p else None
        net = 2 * yaw_distribution(raw, ryh) - 1 if raw is not None else torch.cos(ryh - p["net_ry"][sl].double()[:, None])
        a_true = math.degrees(math.atan2(math.sin(tr - ray), math.cos(tr - ray)))
        outrows.append(dict(o, side=float(p["border_side"][j]) if "border_side" in p else 0.0, alpha_true=a_true,
                            lamp_present=bool(p["lamp_present"][j]), lamp_usable=bool(p["lamp_usable"][j]), lamp_offset=float(p["lamp_offset"][j]),
                            front_present=bool(p["front_present"][j]) if "front_present" in p else None,
                            front_usable=bool(p["front_usable"][j]) if "front_usable" in p else None,
                            lamps_true=float(lam[0, 0]), lamps_rev=float(lam[0, 1]), net_true=float(net[0, 0]), net_rev=float(net[0, 1]),
                            net_ry=float(p["net_ry"][j]), branch_ry=float(p["ry"][j])))
json.dump(outrows, open(out, "w"))
fl = [r for r in outrows if r["yaw_deg"] > 90]
print(f"{tree}: {len(fl)} flipped of {len(outrows)}; cut (side!=0) {sum(r['side']!=0 for r in outrows)}, flipped among cut {sum(r['side']!=0 for r in fl)}")
