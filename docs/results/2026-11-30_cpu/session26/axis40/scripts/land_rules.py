"""land_rules.py TREE...: replays axis rules on landscape.py's refits (/tmp/s26data/axis40/land_TREE) joined to the
fit's own fine hypotheses (a diag_pose.py run of the same code on the same tree: DIAG, default the session 25 lead's
main diag /tmp/s25data/lead/axis/pose/main_TREE.diag.json), row gt_fit (ground-truth masks + boxes, an oracle; the
truth only scores). A rule names a candidate axis from the fine hypotheses; the refit started nearest that axis at the
winner's end (landscape.py's 10-degree grid, within 40 degrees of the winner) replaces the winner where its loss is
lower than ``against``: the winner's own loss (``won``) or the refit from the winner's own yaw (``refit``, the same
number of steps). Usage: python land_rules.py 35 37
"""
import json
import math
import os
import sys

import numpy as np

ROW = "fit, oracle: ground-truth masks + boxes"


def wrap(d: float) -> float:
    return math.atan2(math.sin(d), math.cos(d))


def axis_err(ry: float, true: float) -> float:
    e = abs(math.degrees(wrap(ry - true)))
    return min(e, 180 - e)


def ci(d: np.ndarray) -> str:
    rng = np.random.default_rng(0)
    m = d[rng.integers(0, len(d), (10_000, len(d)))].mean(1)
    lo, hi = np.percentile(m, [2.5, 97.5])
    return f"{d.mean():+.2f} [{lo:+.2f}, {hi:+.2f}] {int((d < -0.5).sum())}/{int((d > 0.5).sum())}"


def candidate(rule: str, d: dict, w: int) -> int | None:
    """The fine hypothesis whose axis the rule refits, or None."""
    loss, ry = d["loss"], d["hyp_ry"]
    other = [h for h in range(len(ry)) if axis_err(ry[h], ry[w]) > 10 and math.isfinite(loss[h])]
    if rule == "brief":  # the lowest loss of all lies on the other end, on another axis
        b = min(range(len(ry)), key=lambda h: loss[h])
        return b if b in other and math.cos(ry[b] - ry[w]) < 0 else None
    if rule == "best other axis":
        return min(other, key=lambda h: loss[h]) if other else None
    if rule == "best other axis, reversed end":
        rev = [h for h in other if math.cos(ry[h] - ry[w]) < 0]
        return min(rev, key=lambda h: loss[h]) if rev else None
    raise ValueError(rule)


def main() -> None:
    rows = []
    for t in sys.argv[1:]:
        p = f"/tmp/s26data/axis40/land_{t}"
        table = json.load(open(p + ".json"))["objects"][ROW]
        land = {(d["frame"], d["ry"]): d for d in json.load(open(p + ".land.json"))}
        diag = {(d["frame"], d["ry"]): d for d in json.load(open(os.environ.get(
            "DIAG", f"/tmp/s25data/lead/axis/pose/main_{t}.diag.json").replace("TREE", t))) if d["row"] == "gt_fit"}
        for o in table:
            k = (o["frame"], o["ry"])
            if k in land and k in diag and land[k]["fitted"]:
                rows.append((o, land[k], diag[k]))
    print(f"{len(rows)} cars, ground-truth masks + boxes (oracle)")
    for rule in ("brief", "best other axis", "best other axis, reversed end"):
        for against in ("won", "refit"):
            ax, yaw, acted, moved = [], [], 0, 0
            for o, land, d in rows:
                w = min(range(len(d["hyp_ry"])), key=lambda h: abs(wrap(d["hyp_ry"][h] - o["ry"])))
                ry = o["ry"]
                c = candidate(rule, d, w)
                offs = [math.degrees(wrap(s - o["ry"])) for s in land["start"]]
                if c is not None:
                    # the candidate's axis at the winner's end, as an offset from the winner's yaw
                    target = math.degrees(wrap(d["hyp_ry"][c] - o["ry"]))
                    if abs(target) > 90:
                        target = math.degrees(wrap(math.radians(target + 180)))
                    if abs(target) <= 45:
                        acted += 1
                        i = min(range(len(offs)), key=lambda j: abs(offs[j] - target))
                        zero = min(range(len(offs)), key=lambda j: abs(offs[j]))
                        bar = land["win_loss"] if against == "won" else land["loss"][zero]
                        if land["loss"][i] < bar:
                            ry, moved = land["end"][i], moved + 1
                ax.append(axis_err(ry, o["true_ry"]) - axis_err(o["ry"], o["true_ry"]))
                yaw.append(abs(math.degrees(wrap(ry - o["true_ry"]))) - o["yaw_deg"])
            print(f"{rule:30} against {against:5}: acts on {acted}, moves {moved}; axis error {ci(np.array(ax))}; "
                  f"yaw error {ci(np.array(yaw))}")


if __name__ == "__main__":
    main()
