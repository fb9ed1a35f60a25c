"""Per-function cumulative ms per edit of cProfile runs of session14/cost/draw_edits.py --profile (the 14 latency
edits), this branch's runs against main's (each argument NAME=A.prof,B.prof,...: the runs of one code, averaged), for
the functions this branch changed or whose callees it changed, with the ratio new/main.

    python functions.py new=N1.prof,N2.prof main=M1.prof,M2.prof
"""

import pstats
import sys

FUNCTIONS = ("render_photo", "__init__", "_rasterize", "rasterize_meshes", "_empty_fragments", "_row_spans",
             "_draw", "_surface_points", "_visible", "_part_map", "_raster_ids", "_source_light", "normal_map",
             "compose_instances", "_part_examples", "thin_occluders")
FILES = {"__init__": "transfer.py"}
runs = {}
for arg in sys.argv[1:]:
    name, paths = arg.split("=")
    totals: dict[str, list[float]] = {}
    for path in paths.split(","):
        stats = pstats.Stats(path).stats
        for (file, _, function), (_, _, _, cumtime, _) in stats.items():
            if function in FUNCTIONS and "sdn3d" in file and file.endswith(FILES.get(function, ".py")):
                totals.setdefault(function, []).append(1000 * cumtime / 14)
    runs[name] = {f: sum(v) / len(paths.split(",")) for f, v in totals.items()}
new, main = runs["new"], runs["main"]
print("function (cumulative ms per edit under cProfile, mean of the runs) | new | main | new/main")
for function in FUNCTIONS:
    a, b = new.get(function, 0.0), main.get(function, 0.0)
    ratio = f"{a / b:.3f}" if b else "-"
    print(f"{function:18s} | {a:7.1f} | {b:7.1f} | {ratio}")
