# ruff: noqa: B905, E401, E402, E501, E701, E702, F401, F841, I001
"""cutcars36.py TREE W OUT [W H] (session 34's cutcars.py, its variants left out): per car of a (tuning) tree, row gt_fit (ground-truth masks + boxes), the truth, the
fit, and what the appearance read (lamps, border side, bins' belief) at the truth's yaw and its reverse."""
import sys, math, json, torch, numpy as np
import sdn3d.derender as D
from sdn3d.models import Models
from sdn3d.geometric.lamps import LampCue, evidence_of
from sdn3d.geometric.model import yaw_distribution
sys.path.insert(0, "/tmp/s36_flips/benchmarks")
import pose_table

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
