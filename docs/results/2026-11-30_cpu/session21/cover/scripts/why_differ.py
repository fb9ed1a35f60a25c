# ruff: noqa: E402
"""Why the branch's fill differs from main's on the pixels seen: for each edit of draw_edits.py's tree (the branch's
code on PYTHONPATH; --only for a subset), every ``ray_fill`` call with ``drawn_over`` is run again without it (main's
whole-hole fill) and the two are compared on the pixels filled by both: the grain weight each fitted
(``_matched_weight``), the rays that took the far side's road in a verge run (``_ended_verge_runs``), the pixels whose
ray value differs, and the seen pixels no ray reached (Telea's; counted in ``fill_hole``).

    python why_differ.py TREE OUT [--only 1,4,6]
    python why_differ.py probe.py RUN_DIR OUT_DIR only=12002_turned   # another script's edits (its arguments follow)
"""

import runpy
import sys

import torch

import sdn3d.editing.photo.road as road

DRAW_EDITS = "docs/results/2026-11-30_cpu/session21/cover/scripts/draw_edits.py"
ray_fill = road.ray_fill
matched = road._matched_weight
ended = road._ended_verge_runs
log: dict[str, list] = {"weight": [], "ended": []}
rows: list[str] = []


def recorded_weight(*a, **k):
    w = matched(*a, **k)
    log["weight"].append(w)
    return w


def recorded_ended(*a, **k):
    e = ended(*a, **k)
    log["ended"].append(int(e.sum()))
    return e


def compared_fill(image, hole, *a, drawn_over=None, **k):
    log["weight"].clear()
    log["ended"].clear()
    part, reached_part = ray_fill(image, hole, *a, drawn_over=drawn_over, **k)
    if drawn_over is None:
        return part, reached_part
    w_part, e_part = list(log["weight"]), list(log["ended"])
    log["weight"].clear()
    log["ended"].clear()
    whole, reached = ray_fill(image, hole, *a, **k)
    both = reached_part & reached
    differ = (part != whole).any(0) & both
    seen = hole & ~drawn_over
    rows.append(f"| {int(hole.sum())} | {int((hole & drawn_over).sum())} | {w_part} / {log['weight']} | "
                f"{e_part} / {log['ended']} | {int(both.sum())} | {int(differ.sum())} | "
                f"{int((seen & ~reached_part).sum())} | {int((seen & ~reached).sum())} |")
    return part, reached_part


road.ray_fill = compared_fill
road._matched_weight = recorded_weight
road._ended_verge_runs = recorded_ended
torch.set_num_threads(1)
script = sys.argv[1] if sys.argv[1].endswith(".py") else DRAW_EDITS
sys.argv = [script, *sys.argv[1 + (script != DRAW_EDITS):]]
try:
    runpy.run_path(script, run_name="__main__")
except SystemExit:
    pass
print("| hole | drawn over | grain weight (branch / main) | verge-run rays (branch / main) | filled by both | "
      "differing there | seen, unreached (branch) | (main) |")
print("|---|---|---|---|---|---|---|---|")
print("\n".join(rows))
