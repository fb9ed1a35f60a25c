# ruff: noqa: E402
"""runvar.py BENCH_ARGS...: sdn3d-bench (tunev.sh) with the tuning variants of the library code it imports, named in
the environment variable VARIANT (comma-separated): nopartrefl (transfer.PART_VIEW_REFLECTION off), gk=N (a
never-seen glass point takes the mean of N examples everywhere, the snapshot code's own rule replaced). The variants
a, aglass, abody of the README were earlier snapshots of transfer._reflect_part_colors (every part, glass only, body
only), b / c / d snapshots of the work tree (README, section 2)."""

import os

import sdn3d.editing.photo.transfer as transfer
from sdn3d.meshes.parts import Part

VARIANT = os.environ.get("VARIANT", "").split(",")
if "nopartrefl" in VARIANT:
    transfer.PART_VIEW_REFLECTION = False
for name in VARIANT:
    if name.startswith("gk="):
        more = int(name[3:])
        part_colors = transfer._part_colors

        def _glass_more(b, own, seen_colors, points, normals, parts, before, body, others=None, max_examples=1500,
                        k=4, _more=more, _orig=part_colors):
            colour, code, seen = _orig(b, own, seen_colors, points, normals, parts, before, body, others,
                                       max_examples, k)
            glass = parts == int(Part.GLASS)
            if bool(glass.any()):
                colour[glass], code[glass], seen[glass] = _orig(b, own, seen_colors, points[glass], normals[glass],
                                                                parts[glass], before, body, others, max_examples,
                                                                _more)
            return colour, code, seen

        transfer._part_colors = _glass_more

from sdn3d.cli.bench import main

main()
