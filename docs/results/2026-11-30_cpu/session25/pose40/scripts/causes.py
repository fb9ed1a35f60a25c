"""causes.py PREFIX... [--list]: why the fit on predicted proposals flips cars that the fit on ground-truth masks
(an oracle) does not. PREFIX: diag.sh's output prefix (PREFIX.json the pose table with rows gt_fit and pred_fit,
PREFIX.diag.json diag_pose.py's decisions with each mask's quality against the truth).

Per car matched in the predicted row (its proposal's IoU with its true visible mask at least 0.5): both rows' yaw
errors, the proposal's quality (iou, cover, merged, stray: diag_pose.py's module doc), each row's lamp reading and
border side, and at the TRUE yaw (the truth an oracle, used only to score) the belief's verdict (the fit's belief at
the true yaw minus at its reverse: right when > 0), split into the lamps' part and the bins' part, and whether the
fine stage had a hypothesis within 90 degrees of the truth and how its loss compared with the winner's. Each
predicted flip gets one cause, the first that applies:

- ``no right hypothesis``: no fine hypothesis ended within 90 degrees of the truth;
- ``belief wrong: lamps`` / ``belief wrong: bins``: the belief preferred the wrong end, and the lamps' part (or, with
  the lamps abstaining or right, the bins' part) was wrong;
- ``silhouette``: the belief was right, and a wrong-end fit's loss won (more than facing_tie lower, or the right-end
  fit's loss out of reach);
- ``other``.
Run with a code's library on the path (PYTHONPATH=TREE/src) whose facing_belief the diag recorded."""
import argparse
import json
import math
from collections import Counter, defaultdict

import torch

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.lamps import LampCue, evidence_of
from sdn3d.geometric.model import yaw_distribution

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}


def wrap_deg(d: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(d), math.cos(d))))


def reading(app: dict) -> str:
    if app["lamp_usable"]:
        return "red" if app["lamp_present"] else "no red"
    if app.get("front_usable"):
        return "redbody white" if app["front_present"] else "redbody no white"
    return "unreadable"


def verdict(app: dict, cue: LampCue, ry_true: float) -> tuple[float, float, float]:
    """(total, lamps, bins) belief at the true yaw minus at its reverse."""
    v = {k: torch.tensor(x)[None] for k, x in app.items()}
    ry = torch.tensor([[ry_true, ry_true + math.pi]])
    total = facing_belief(v, cue)(ry)
    alpha = ry - v["ray"][:, None]
    front = (v["front_present"].bool(), v["front_usable"].bool(), v["front_offset"]) if "front_usable" in v else None
    border = v.get("border_side")
    lamps = evidence_of(v["lamp_present"].bool(), v["lamp_usable"].bool(), v["lamp_offset"], alpha, cue,
                        front=front, border=border)
    net = -cue.flip_below * (2 * yaw_distribution({k: v[k] for k in ("yaw_bins", "yaw_residual", "yaw_ray")}, ry) - 1)
    d = (total[0, 0] - total[0, 1], lamps[0, 0] - lamps[0, 1], net[0, 0] - net[0, 1])
    return tuple(float(x) for x in d)


def load(prefix: str) -> list[dict]:
    table = json.load(open(prefix + ".json"))
    diag = json.load(open(prefix + ".diag.json"))
    gt_diag = defaultdict(list)
    pred_diag = defaultdict(list)
    for d in diag:
        if d["row"] == "gt_fit":
            gt_diag[(d["frame"], d["ry"])].append(d)
        elif d["row"] == "pred_fit":
            pred_diag[(d["frame"], d["ry"])].append(d)
    gt = {(o["frame"], o["id"]): o for o in table["objects"][ROWS["gt_fit"]]}
    cars = []
    for o in table["objects"][ROWS["pred_fit"]]:
        if not o["matched"]:
            continue
        g = gt[(o["frame"], o["id"])]
        hp, hg = pred_diag.get((o["frame"], o["ry"]), []), gt_diag.get((g["frame"], g["ry"]), [])
        hp = [d for d in hp if d.get("gt_id") == o["id"]] or hp
        cars.append({"tree": prefix.rsplit("_", 1)[-1], "pred": o, "gt": g, "dp": hp[0] if len(hp) == 1 else None,
                     "dg": hg[0] if len(hg) == 1 else None})
    return cars


def cause(d: dict, ry_true: float, facing_tie: float = 0.5) -> tuple[str, dict]:
    cue = LampCue(**d["cue"])
    total, lamps, bins = verdict(d["app"], cue, ry_true)
    errs = [wrap_deg(r - ry_true) for r in d["hyp_ry"]]
    right = [i for i, e in enumerate(errs) if e <= 90]
    info = {"belief": total, "lamps": lamps, "bins": bins, "reading": reading(d["app"]),
            "border": d["app"].get("border_side", 0.0), "hyp": d["winner"]}
    if not right:
        return "no right hypothesis", info
    best_right = min(right, key=lambda i: d["loss"][i])
    info["loss_ratio"] = d["loss"][best_right] / max(d["loss"][d["winner"]], 1e-9)
    if total < 0:
        return ("belief wrong: lamps" if lamps < 0 else "belief wrong: bins"), info
    if total > 0:
        return "silhouette", info
    return "other", info


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    cars = [c for p in a.prefixes for c in load(p)]
    n = len(cars)
    fp = [c for c in cars if c["pred"]["yaw_deg"] > 90]
    fg = [c for c in cars if c["gt"]["yaw_deg"] > 90]
    print(f"matched cars {n}: predicted flips {len(fp)} ({100 * len(fp) / n:.1f} %), ground-truth masks (oracle) "
          f"flips on the same cars {len(fg)} ({100 * len(fg) / n:.1f} %), both {sum(c in fg for c in fp)}")
    causes = Counter()
    quality = defaultdict(list)
    for c in cars:
        flip = c["pred"]["yaw_deg"] > 90
        dp = c["dp"]
        if dp is None:
            continue
        band = ("iou<0.7" if dp["iou"] < 0.7 else "iou 0.7-0.85" if dp["iou"] < 0.85 else "iou>=0.85")
        quality[band].append(flip)
        quality["merged>0.1" if dp["merged"] > 0.1 else "merged<=0.1"].append(flip)
        quality["cover<0.8" if dp["cover"] < 0.8 else "cover>=0.8"].append(flip)
    print("predicted flip share by the proposal's quality:")
    for k in sorted(quality):
        v = quality[k]
        print(f"  {k:14} {sum(v):3d} / {len(v):3d} ({100 * sum(v) / max(len(v), 1):.1f} %)")
    print("flipped predicted cars (tree frame id px: pred err, oracle err | mask iou cover merged stray | "
          "pred reading/border, oracle reading/border | cause [belief lamps bins] hyp loss ratio):")
    for c in sorted(fp, key=lambda c: (c["tree"], c["pred"]["frame"], c["pred"]["id"])):
        dp, dg, o = c["dp"], c["dg"], c["pred"]
        if dp is None or "app" not in dp:
            causes["(no diag)"] += 1
            print(f"  {c['tree']} {o['frame']} {o['id']}: no diag")
            continue
        why, info = cause(dp, o["true_ry"])
        causes[why] += 1
        gtxt = "-"
        if dg is not None and "app" in dg:
            _, ginfo = cause(dg, o["true_ry"])
            gtxt = f"{ginfo['reading']}/{ginfo['border']:+.0f} [{ginfo['belief']:+.2f} {ginfo['lamps']:+.2f} " \
                   f"{ginfo['bins']:+.2f}]"
        print(f"  {c['tree']} {o['frame'][8:]:20} {o['id']} px {o['pixels']:4d}: {o['yaw_deg']:5.1f} "
              f"{c['gt']['yaw_deg']:5.1f} | {dp['iou']:.2f} {dp['cover']:.2f} {dp['merged']:.2f} {dp['stray']:.2f} "
              f"| {info['reading']}/{info['border']:+.0f} vs {gtxt} | {why} [{info['belief']:+.2f} "
              f"{info['lamps']:+.2f} {info['bins']:+.2f}] h{info['hyp']} {info.get('loss_ratio', float('nan')):.2f}")
    print("causes:", dict(causes))
    if a.list:
        agree = Counter()
        for c in cars:
            if c["dp"] is None or c["dg"] is None or "app" not in c["dp"] or "app" not in c["dg"]:
                continue
            agree[(reading(c["dg"]["app"]), reading(c["dp"]["app"]))] += 1
        print("lamp reading, oracle -> predicted (all matched cars):")
        for k, v in sorted(agree.items()):
            print(f"  {k[0]:16} -> {k[1]:16} {v}")


if __name__ == "__main__":
    main()
