# ruff: noqa: E402
"""Which ``_part_examples`` calls of the photo path made examples that nothing used (``_examples_of_part``,
``_reflection_strength``, ``_part_colors``, ``_reflect_part_colors`` never received them), with each call's wall time,
during session 14's draw_edits.py (its arguments follow, e.g. ``--only 0,1,3,6,10,11`` for the latency turns; the
warm-up edit is included). Run on main: the calls the lazy clear-air reading (this branch) no longer makes.

    python unused_examples.py TREE OUT [draw_edits args...]
"""

import runpy
import sys
import time

import sdn3d.editing.photo.transfer as transfer

DRAW_EDITS = "docs/results/2026-11-29_cpu/session14/cost/draw_edits.py"
made: dict[int, list] = {}  # id(examples) -> [ms, used, visible pixels, examples, the examples (kept: no id reused)]
part_examples = transfer._part_examples


def recorded(*args, **kwargs):
    t0 = time.perf_counter()
    out = part_examples(*args, **kwargs)
    made[id(out[0])] = [1000 * (time.perf_counter() - t0), False, len(args[2]), len(out[0].part), out[0]]
    return out


def marking(name):
    fn = getattr(transfer, name)

    def wrapper(*args, **kwargs):
        for x in (*args, *kwargs.values()):
            if isinstance(x, transfer._PartExamples) and id(x) in made:
                made[id(x)][1] = True
        return fn(*args, **kwargs)
    setattr(transfer, name, wrapper)


transfer._part_examples = recorded
for name in ("_examples_of_part", "_reflection_strength", "_part_colors", "_reflect_part_colors"):
    marking(name)
sys.argv = [DRAW_EDITS, *sys.argv[1:]]
runpy.run_path(DRAW_EDITS, run_name="__main__")
for label, rows in (("used", [v for v in made.values() if v[1]]), ("unused", [v for v in made.values() if not v[1]])):
    print(f"{label}: {len(rows)} calls, {sum(v[0] for v in rows):.0f} ms wall in all; "
          f"(ms, visible pixels, examples) {[(round(v[0], 1), v[2], v[3]) for v in rows]}")
