"""flips.py PREFIX...: every car flipped (yaw error > 90 degrees) by the fit, on ground-truth masks + boxes (an
oracle: row gt_fit) and on predicted proposals (row pred_fit, matched cars), with one cause each, and the causes
counted. PREFIX: diag.sh's output prefix (PREFIX.json the pose table, PREFIX.diag.json diag_pose.py's decisions);
its last ``_NN`` names the tree. Run with a code's library on the path (PYTHONPATH=TREE/src):

    PYTHONPATH=/tmp/s25data/lead/base_9a6/src python flips.py /tmp/s25data/pose40/main_31 ... > flips_main.txt

Causes (the first that applies; the truth is an oracle, read only to score):

- ``no right hypothesis``: no fine hypothesis within 90 degrees of the truth;
- ``border rule``: the belief preferred the wrong end and its lamps' part is the traffic side's (the box cut by the
  left or right border, no lamps seen: lamps.py's ``_cut_absence``);
- ``lamps: <reading>``: the belief preferred the wrong end and the lamps' part (a reading of the crop) was wrong;
- ``bins``: the belief preferred the wrong end, the lamps abstaining or right: the MultiBin bins;
- ``silhouette on axis``: the belief was right and a wrong-end fit on the right end's axis (within FACING_AXIS of
  180 degrees of a right-end fit) won by more than facing_tie;
- ``silhouette off axis``: the belief was right and the wrong-end winner has no right-end fit on its axis (the
  right end's fits lie on another axis, e.g. the depth reflection);
- ``other``.
"""
import argparse
import json
import math
from collections import Counter, defaultdict

import torch

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.lamps import LampCue, evidence_of
from sdn3d.geometric.model import yaw_distribution

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}
AXIS = math.radians(30)


def wrap(d: float) -> float:
    return math.atan2(math.sin(d), math.cos(d))


def reading(app: dict) -> str:
    if app["lamp_usable"]:
        return "red" if app["lamp_present"] else "no red"
    if app.get("front_usable"):
        return "redbody white" if app["front_present"] else "redbody no white"
    return "unreadable"


def parts(app: dict, cue: LampCue, ry_true: float) -> tuple[float, float, float]:
    """(total, lamps, bins): the belief at the true yaw minus at its reverse (> 0: right)."""
    v = {k: torch.tensor(x)[None] for k, x in app.items()}
    ry = torch.tensor([[ry_true, ry_true + math.pi]])
    total = facing_belief(v, cue)(ry)
    alpha = ry - v["ray"][:, None]
    front = (v["front_present"].bool(), v["front_usable"].bool(), v["front_offset"]) if "front_usable" in v else None
    lamps = evidence_of(v["lamp_present"].bool(), v["lamp_usable"].bool(), v["lamp_offset"], alpha, cue,
                        front=front, border=v.get("border_side"))
    net = -cue.flip_below * (2 * yaw_distribution({k: v[k] for k in ("yaw_bins", "yaw_residual", "yaw_ray")}, ry) - 1)
    return tuple(float(x[0, 0] - x[0, 1]) for x in (total, lamps, net))


def cause(d: dict, ry_true: float, ry_final: float) -> tuple[str, dict]:
    cue = LampCue(**d["cue"])
    # the winner: the hypothesis the object's final yaw is (the recorded index is the outward choice's)
    d = {**d, "winner": min(range(len(d["hyp_ry"])), key=lambda i: abs(wrap(d["hyp_ry"][i] - ry_final)))}
    total, lamps, bins = parts(d["app"], cue, ry_true)
    errs = [abs(wrap(r - ry_true)) for r in d["hyp_ry"]]
    right = [i for i, e in enumerate(errs) if e <= math.pi / 2]
    border = d["app"].get("border_side", 0.0)
    red = reading(d["app"])
    info = {"belief": total, "lamps": lamps, "bins": bins, "reading": red, "border": border, "hyp": d["winner"],
            "win_loss": d["loss"][d["winner"]]}
    if not right:
        return "no right hypothesis", info
    best_right = min(right, key=lambda i: d["loss"][i])
    info["loss_ratio"] = d["loss"][best_right] / max(d["loss"][d["winner"]], 1e-9)
    if total < 0:
        absent = red in ("no red", "redbody no white", "unreadable")
        if lamps < 0 and border != 0 and absent:
            return "border rule", info
        if lamps < 0:
            return f"lamps: {red}", info
        return "bins", info
    if total > 0:
        w = d["hyp_ry"][d["winner"]]
        on_axis = any(abs(wrap(d["hyp_ry"][i] - w - math.pi)) <= AXIS for i in right)
        return ("silhouette on axis" if on_axis else "silhouette off axis"), info
    return "other", info


def load(prefix: str) -> dict[str, list[dict]]:
    table = json.load(open(prefix + ".json"))
    diag = json.load(open(prefix + ".diag.json"))
    by = defaultdict(list)
    for d in diag:
        by[(d["row"], d["frame"], d["ry"])].append(d)
    tree = prefix.rsplit("_", 1)[-1]
    out = {}
    for row, name in ROWS.items():
        cars = []
        for o in table["objects"].get(name, []):
            if row == "pred_fit" and not o["matched"]:
                continue
            hs = by.get((row, o["frame"], o["ry"]), [])
            hs = [d for d in hs if d.get("gt_id") in (None, o["id"])] or hs
            cars.append({"tree": tree, "o": o, "d": hs[0] if len(hs) == 1 else None})
        out[row] = cars
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("prefixes", nargs="+")
    a = ap.parse_args()
    rows = defaultdict(list)
    for p in a.prefixes:
        for row, cars in load(p).items():
            rows[row] += cars
    for row, cars in rows.items():
        flips = [c for c in cars if c["o"]["yaw_deg"] > 90]
        print(f"== {ROWS[row]}: {len(cars)} cars, {len(flips)} flipped ({100 * len(flips) / max(len(cars), 1):.1f} %)")
        print("  tree frame id px: err | reading/border | cause [belief lamps bins] winner loss ratio")
        count = Counter()
        for c in sorted(flips, key=lambda c: (c["tree"], c["o"]["frame"], c["o"]["id"])):
            o, d = c["o"], c["d"]
            if d is None or "app" not in d:
                count["(no diag)"] += 1
                print(f"  {c['tree']} {o['frame'][8:]:20} {o['id']}: no diag")
                continue
            why, info = cause(d, o["true_ry"], o["ry"])
            count[why] += 1
            q = f" | iou {d['iou']:.2f} stray {d['stray']:.2f}" if row == "pred_fit" and "iou" in d else ""
            print(f"  {c['tree']} {o['frame'][8:]:20} {o['id']} px {o['pixels']:4d}: {o['yaw_deg']:5.1f} | "
                  f"{info['reading']}/{info['border']:+.0f} | {why} [{info['belief']:+.2f} {info['lamps']:+.2f} "
                  f"{info['bins']:+.2f}] h{info['hyp']} {info.get('loss_ratio', float('nan')):.2f}{q}")
        print("  causes:", dict(count.most_common()))


if __name__ == "__main__":
    main()
