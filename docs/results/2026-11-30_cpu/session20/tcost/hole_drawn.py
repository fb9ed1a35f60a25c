# ruff: noqa: E402
"""How much of a turn's fill the drawing then covers: for each edit of session 14's draw_edits.py (its arguments
follow; use --only for the turns), the hole that ``fill_hole`` filled, the share of its pixels the edit's drawn
objects then covered (their result code is not ``fill``), and the wall time of ``fill_hole`` on that hole and on its
uncovered pixels alone (the same call otherwise; the least of 3 each, alternating). A measurement for a possible cut
that would change outputs (a fill of the uncovered pixels alone, the covered ones still no source of the rays: not
what the second call does, which also lets rays start inside the covered part); nothing here changes the code.

    python hole_drawn.py TREE OUT [draw_edits args...]
"""

import runpy
import sys
import time

import sdn3d.editing.appearance as appearance
import sdn3d.editing.photo.transfer as transfer

DRAW_EDITS = "docs/results/2026-11-29_cpu/session14/cost/draw_edits.py"
holes: list[tuple] = []
fill_hole = transfer.fill_hole


def recorded_fill(image, hole, *args, **kwargs):
    holes.append((image, hole.clone(), args, kwargs))
    return fill_hole(image, hole, *args, **kwargs)


def least_time(image, hole, args, kwargs) -> float:
    t0 = time.perf_counter()
    fill_hole(image, hole, *args, **kwargs)
    return time.perf_counter() - t0


transfer.fill_hole = recorded_fill
draw = appearance.PhotoRenderer.draw
rows: list[str] = []


def measured_draw(self, *a, **k):
    holes.clear()
    drawn = draw(self, *a, **k)
    if holes:
        image, hole, args, kwargs = holes[-1]
        covered = hole & (drawn.photo.source != transfer.FILL)
        whole, rest = [], []
        for _ in range(3):
            whole.append(least_time(image, hole, args, kwargs))
            rest.append(least_time(image, hole & ~covered, args, kwargs))
        rows.append(f"| {int(hole.sum())} | {int(covered.sum())} | {covered.sum() / hole.sum().clamp(min=1):.3f} | "
                    f"{1000 * min(whole):.0f} | {1000 * min(rest):.0f} |")
    return drawn


appearance.PhotoRenderer.draw = measured_draw
sys.argv = [DRAW_EDITS, *sys.argv[1:]]
runpy.run_path(DRAW_EDITS, run_name="__main__")
print("| hole pixels | covered by the drawn objects | share | fill_hole ms, the hole | the uncovered pixels alone |")
print("|---|---|---|---|---|")
print("\n".join(rows[1:]))  # the warm-up edit first
