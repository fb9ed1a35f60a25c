"""Session 21 side, the held-out 2199 diagnosis (made after that measurement): ``sdn3d-bench`` run with a code tree's
``transfer._paint_off_the_band`` recorded, per car and call: whether it fired, the share of the examples off the lamp
band that are of the whole body's paint, and the CIE Lab medians of all body examples, those off the band and those at
it. Lines go to OUT_TXT.

    cd TREE && PYTHONPATH=TREE/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python decisions_probe.py OUT_TXT \\
        counterfactual=true data.root=... output_dir=... examples=0 threads=1 "counterfactual_kinds=[turn]" ...
"""

from __future__ import annotations

import sys

import sdn3d.editing.photo.transfer as T
from sdn3d.cli.bench import main
from sdn3d.editing.photo.recolor import body_paint

CURRENT: dict = {}
LOG = open(sys.argv[1], "w")  # noqa: SIM115 (open for the whole run)
_part_examples = T._part_examples
_paint_off_the_band = T._paint_off_the_band


def part_examples(b, s_mesh, visible_px, before, *rest):
    CURRENT.update(iid=int(before.instance_id[b]), visible=len(visible_px))
    return _part_examples(b, s_mesh, visible_px, before, *rest)


def paint_off_the_band(lab, band):
    fired = _paint_off_the_band(lab, band)
    off = band < 0
    share = float(body_paint(lab[off], reference=lab)[0].double().mean())
    at = lab[~off].median(0).values.numpy().round(1) if bool((~off).any()) else None
    print(CURRENT, "fired" if fired else "no", f"share {share:.3f}", "all", lab.median(0).values.numpy().round(1),
          "off", lab[off].median(0).values.numpy().round(1), "at", at, file=LOG, flush=True)
    return fired


T._part_examples = part_examples
T._paint_off_the_band = paint_off_the_band
sys.exit(main(sys.argv[2:]))
