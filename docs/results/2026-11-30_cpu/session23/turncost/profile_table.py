"""profile_table.py PROF TURNS [PROF TURNS ...]: cumulative CPU ms per turn of the photo path's stages in cProfile
dumps (profile_cpu.py's or editor/editor_turns.py's, CPU clock), one column per dump (TURNS: the turns it holds).

    python profile_table.py main.prof 6 branch.prof 6
"""

import pstats
import sys

STAGES = [
    ("appearance.py", "draw", "draw (a fresh source: PhotoSource, then render_photo)"),
    ("transfer.py", "render_photo", "render_photo"),
    ("transfer.py", "__init__", "PhotoSource.__init__ (fresh source)"),
    ("transfer.py", "removal", "the removal (fill, leftovers, vanishing point)"),
    ("road.py", "ray_fill", "of it ray_fill"),
    ("road.py", "_trace", "of it _trace (the rays)"),
    ("fill.py", "removal_guides", "of it removal_guides"),
    ("road.py", "shadowed_road", "of it shadowed_road"),
    ("transfer.py", "_draw", "_draw"),
    ("transfer.py", "_part_colors", "of it _part_colors"),
    ("transfer.py", "_nearest_examples", "of it _nearest_examples"),
    ("transfer.py", "_part_examples", "of it _part_examples"),
    ("recolor.py", "ground_in_mask", "of it ground_in_mask"),
    ("transfer.py", "_rasterize", "_rasterize (source and target)"),
    ("transfer.py", "_paste_near_views", "_paste_near_views"),
    ("transfer.py", "seen_through_the_air", "seen_through_the_air"),
]


def cumulative(stats: pstats.Stats) -> dict[tuple[str, str], float]:
    out: dict[tuple[str, str], float] = {}
    for (path, _, name), (_, _, _, ct, _) in stats.stats.items():
        key = (path.rsplit("/", 1)[-1], name)
        out[key] = out.get(key, 0.0) + ct
    return out


args = sys.argv[1:]
dumps = [(args[i], int(args[i + 1])) for i in range(0, len(args), 2)]
tables = [(cumulative(pstats.Stats(p)), n) for p, n in dumps]
print("| stage | " + " | ".join(f"{p} (ms per turn)" for p, _ in dumps) + " |")
print("|---|" + "---|" * len(dumps))
for module, name, label in STAGES:
    cells = [f"{1000 * t.get((module, name), 0.0) / n:.0f}" for t, n in tables]
    print(f"| {label} | " + " | ".join(cells) + " |")
