"""choices.py PREFIX [PREFIX ...]: offline choice rules on spy.sh's records (PREFIX.json pose table, PREFIX.spy.json
hypotheses), fit on ground-truth masks + boxes (an oracle), split by view (views.py's): each rule re-chooses among the
same fine-stage fits (the fits do not depend on the rule), scored against the truth (an oracle, only to score).

Rules: ``main`` (the library's recorded choice; re-computed as a check), ``lowest-loss same end`` (main's
winner's end kept, among the fits within ``tie`` of the best facing within ``AXIS`` degrees of it the lowest loss),
and the length rules on main's winner: ``length: template proportions`` (the winner's template's typical length
scaled by its fitted height and width against the template's), ``length: start`` (the branch's predicted length).
Run with the library of main's tree on PYTHONPATH (for ``fit._choose``).
"""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import torch

from sdn3d.geometric.fit import FitSettings, _choose
from sdn3d.meshes.templates import TEMPLATE_DIMENSIONS, TEMPLATE_NAMES

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from views import boot, view  # noqa: E402

AXIS = math.radians(30)
TYPICAL = np.array([TEMPLATE_DIMENSIONS[n] for n in TEMPLATE_NAMES])


def main_index(r: dict, s: FitSettings) -> int:
    loss, belief = torch.tensor([r["loss"]]), torch.tensor([r["belief"]])
    ry, inward = torch.tensor([r["ry"]]), torch.tensor([r["inward"]])
    index = _choose(loss, belief, ry, s)
    outward = _choose(torch.where(inward & ~inward.all(1, keepdim=True), math.inf, loss), belief, ry, s)
    index = torch.where(belief.gather(1, outward[:, None])[:, 0] >= belief.gather(1, index[:, None])[:, 0],
                        outward, index)
    return int(index[0])


def same_end_lowest(r: dict, i: int, s: FitSettings) -> int:
    loss, ry = np.array(r["loss"]), np.array(r["ry"])
    inward = np.array(r["inward"])
    ok = np.isfinite(loss) & (np.cos(ry - ry[i]) > math.cos(AXIS)) & (inward == inward[i])
    best = loss[np.isfinite(loss)].min()
    ok &= loss <= best * (1 + s.tie)
    ok[i] = True
    cand = np.where(ok)[0]
    return int(cand[np.argmin(loss[cand])])


def main() -> None:
    s = FitSettings()
    rows, recomputed = [], 0
    for prefix in sys.argv[1:]:
        table = json.load(open(prefix + ".json"))["objects"]["fit, oracle: ground-truth masks + boxes"]
        spy = json.load(open(prefix + ".spy.json"))
        records, truth = spy["records"], spy["truth_dims"]
        assert len(records) == len(table), (len(records), len(table))
        for o, r in zip(table, records, strict=True):
            if not r["fitted"]:
                continue
            t_dims = np.array(truth[o["frame"]][str(o["id"])])
            i = r["won"]  # the fit's own winner (the mirror is on: the hypothesis index is the fine stage's)
            recomputed += main_index(r, s) == i  # differs only where the recorded beliefs' rounding ties
            j = same_end_lowest(r, i, s)
            d = np.array(r["dims"][i])
            tpl = r["template"][i]
            prop = TYPICAL[tpl][0] * math.sqrt(d[1] / TYPICAL[tpl][1] * d[2] / TYPICAL[tpl][2])
            rows.append({"view": view(o), "truth": o["true_template"],
                         "main_ok": tpl == o["true_template"], "alt_ok": r["template"][j] == o["true_template"],
                         "main_len": abs(d[0] - t_dims[0]), "alt_len": abs(r["dims"][j][0] - t_dims[0]),
                         "prop_len": abs(prop - t_dims[0]), "start_len": abs(r["start_dims"][0] - t_dims[0]),
                         "changed": j != i, "yaw_changed": abs(math.cos(r["ry"][j] - r["ry"][i]) - 1) > 1e-3})
    print(f"main's rule re-computed on the records: {recomputed} of {len(rows)} winners\n")
    print("| view | cars | main template % | same-end lowest loss % | changed | main length mean m | "
          "same-end length m | template-proportions length m | start length m |")
    print("|---|---|---|---|---|---|---|---|---|")
    for v in ("end on", "oblique", "side", "all"):
        sel = [x for x in rows if v == "all" or x["view"] == v]
        if not sel:
            continue
        dt = np.array([float(x["alt_ok"]) - float(x["main_ok"]) for x in sel])
        lo, hi = boot(dt)
        print(f"| {v} | {len(sel)} | {100 * np.mean([x['main_ok'] for x in sel]):.1f} | "
              f"{100 * np.mean([x['alt_ok'] for x in sel]):.1f} ({100 * dt.mean():+.1f} [{100 * lo:+.1f}, "
              f"{100 * hi:+.1f}]) | {sum(x['changed'] for x in sel)} | {np.mean([x['main_len'] for x in sel]):.3f} | "
              f"{np.mean([x['alt_len'] for x in sel]):.3f} | {np.mean([x['prop_len'] for x in sel]):.3f} | "
              f"{np.mean([x['start_len'] for x in sel]):.3f} |")


if __name__ == "__main__":
    main()
