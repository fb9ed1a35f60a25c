"""score.py PREFIX... [--row gt_fit] [--rule NAME]: diag.sh's pose tables joined to the fit's decisions, per object.

For each object of the row (default the fit on ground-truth masks + boxes, an oracle) that diag_pose.py recorded:
its yaw error, and at the TRUE yaw (the truth an oracle, used only to score) each cue's verdict on front against
back: the lamps' evidence (lamps.evidence_of of the recorded reading) at alpha_true minus at its reverse, and the
MultiBin bins' (2 p - 1). Prints the verdicts by reading (right / wrong / abstain) and every flip (> 90 degrees),
and, with --rule, the flips that the fit's choice (fit._choose on the recorded losses and yaws) would make with
the belief of that rule (RULES below; 'main' must reproduce the recorded winners). Run with the code on the path
whose facing_belief is to be replayed (PYTHONPATH=TREE/src)."""
import argparse
import json
import math
from collections import Counter, defaultdict

import torch

from sdn3d.geometric.facing import facing_belief
from sdn3d.geometric.fit import FitSettings, _choose
from sdn3d.geometric.lamps import LampCue, evidence_of
from sdn3d.geometric.model import yaw_distribution

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}


def wrap_deg(d: float) -> float:
    return abs(math.degrees(math.atan2(math.sin(d), math.cos(d))))


def reading(app: dict, cue: LampCue) -> str:
    if app["lamp_usable"]:
        return "red present" if app["lamp_present"] else "red absent"
    if app.get("front_usable"):
        return "red body, white present" if app["front_present"] else "red body, white absent"
    return "unreadable (red unusable)" if app["lamp_present"] else "unreadable (small)"


def tensors(app: dict) -> dict:
    """One object's recorded appearance as facing_belief's (1, ...) tensors."""
    return {k: torch.tensor(v)[None] for k, v in app.items()}


def cue_terms(app: dict, cue: LampCue, ry: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """(lamps, net) parts of facing_belief at yaws ``ry (1, K)``."""
    v = tensors(app)
    total = facing_belief(v, cue)(ry)
    alpha = ry - v["ray"][:, None]
    front = (v["front_present"].bool(), v["front_usable"].bool(), v["front_offset"]) if "front_usable" in v else None
    lamps = evidence_of(v["lamp_present"].bool(), v["lamp_usable"].bool(), v["lamp_offset"], alpha, cue,
                        front=front)
    raw = {k: v[k] for k in ("yaw_bins", "yaw_residual", "yaw_ray")}
    net = 2 * yaw_distribution(raw, ry) - 1
    assert torch.allclose(total, lamps + (-cue.flip_below) * net, atol=1e-5)
    return lamps, net


def load(prefixes: list[str], row_key: str) -> list[dict]:
    cars = []
    for p in prefixes:
        table = json.load(open(p + ".json"))
        diag = defaultdict(list)
        for d in json.load(open(p + ".diag.json")):
            if d["row"] == row_key:
                diag[(d["frame"], d["ry"])].append(d)
        for o in table["objects"][ROWS[row_key]]:
            hit = diag.get((o["frame"], o["ry"]), [])
            cars.append({**o, "tree": p, "diag": hit[0] if len(hit) == 1 else None})
    return cars


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("prefixes", nargs="+")
    ap.add_argument("--row", default="gt_fit")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    cars = load(a.prefixes, a.row)
    settings = FitSettings()
    tab = defaultdict(Counter)
    flips = []
    replay = Counter()
    for c in cars:
        d = c["diag"]
        if d is None or "app" not in d or not d["has"]:
            tab["(no diag or no prediction)"]["n"] += 1
            continue
        cue = LampCue(**d["cue"])
        app = d["app"]
        ry_t = c["true_ry"]
        lamps, net = cue_terms(app, cue, torch.tensor([[ry_t, ry_t + math.pi]]))
        lv, nv = float(lamps[0, 0] - lamps[0, 1]), float(net[0, 0] - net[0, 1])
        view = math.sin(ry_t - app["ray"])
        view = "side" if abs(view) < 0.3 else ("back" if view < 0 else "front")
        kind = reading(app, cue)
        cut = " | cut" if c["truncated"] else ""
        for key in dict.fromkeys((f"{kind} | {view}{cut}", f"{kind} | {view}", "all")):
            tab[key]["lamps " + ("right" if lv > 1e-6 else "wrong" if lv < -1e-6 else "abstain")] += 1
            tab[key]["bins " + ("right" if nv > 0 else "wrong")] += 1
            tab[key]["n"] += 1
        loss, belief = torch.tensor([d["loss"]]), torch.tensor([d["belief"]])
        ry = torch.tensor([d["hyp_ry"]])
        recomputed = facing_belief(tensors(app), cue)(ry)
        replay["belief reproduced" if torch.allclose(recomputed, belief, atol=1e-4) else "belief differs"] += 1
        replay["winner reproduced" if int(_choose(loss, belief, ry, settings)[0]) == d["winner"] else "w differs"] += 1
        if c["yaw_deg"] > 90:
            flips.append((c, kind, view, lv, nv))
    print(f"== {a.row}: {len(cars)} cars, flips {sum(c['yaw_deg'] > 90 for c in cars)}; replay {dict(replay)}")
    for k in sorted(tab):
        print(f"  {k:45} {dict(tab[k])}")
    print("flips:")
    for c, kind, view, lv, nv in flips:
        tree = c["tree"].rsplit("_", 1)[-1]
        print(f"  {c['yaw_deg']:6.1f} {tree} {c['frame']:26} id {c['id']} px {c['pixels']:5d} cut {int(c['truncated'])}"
              f" {kind:26} {view:5} lamps {lv:+.2f} bins {nv:+.2f} hyp {c['hypothesis']}")


if __name__ == "__main__":
    main()
