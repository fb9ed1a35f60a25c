# ruff: noqa: E402, E501, E701, E702
"""top_costs.py DATA OUT.md [LABEL]: where the photo path's time goes (cProfile timed by the process's CPU time, not the
wall clock: on a loaded machine the wall time of each step grows with the load; cumulative ms per edit, 1 thread,
fresh source state per edit) for each edit kind of the latency tree DATA, with the code on PYTHONPATH; a markdown
table of the main steps (a step's time includes the steps it calls; cProfile adds its own overhead)."""
import cProfile
import pstats
import sys
import time
from pathlib import Path

import torch

torch.set_num_threads(1)
sys.path.insert(0, str(Path(__file__).parent))
from prof import cases

from sdn3d.editing.appearance import appearance_renderer
from sdn3d.editing.photo.settings import PhotoSettings

STEPS = [("appearance.py", "draw", "whole edit (prepare + draw)"), ("transfer.py", "__init__", "PhotoSource (source rasterization, ids, thin occluders)"),
         ("transfer.py", "render_photo", "render_photo"), ("transfer.py", "_remove_with_effects", "fill of the vacated hole (rays, shadow)"),
         ("road.py", "ray_fill", "  ray_fill"), ("road.py", "_trace", "    _trace (rays)"), ("road.py", "_matched_weight", "    _matched_weight (grain)"),
         ("road.py", "road_haze", "    road_haze"), ("road.py", "_along", "    _along"), ("road.py", "shadowed_road", "  shadowed_road"),
         ("road.py", "removal_vanishing_point", "removal_vanishing_point"), ("fill.py", "vacated_hole", "vacated_hole"), ("transfer.py", "_grow", "_grow"),
         ("transfer.py", "_rasterize", "_rasterize (source and target)"), ("transfer.py", "_draw", "_draw (transfer)"),
         ("transfer.py", "_part_colors", "  _part_colors (unseen parts)"), ("transfer.py", "_part_examples", "  _part_examples"),
         ("transfer.py", "_paste_near_views", "_paste_near_views"), ("maps.py", "compose_instances", "compose_instances"),
         ("occluders.py", "thin_occluders", "thin_occluders"), ("recolor.py", "srgb_to_lab", "srgb_to_lab (all calls)")]

if __name__ == "__main__":
    data, out = sys.argv[1], Path(sys.argv[2])
    label = sys.argv[3] if len(sys.argv) > 3 else "this code"
    cs, frame = cases(data)
    r = appearance_renderer("photo", photo=PhotoSettings(fill="rays"))
    r.draw(r.prepare(cs[0][3], frame, cs[0][1]), cs[0][2])
    kinds = sorted({c[0] for c in cs})
    table = {}; n = {}; cpu = {}
    for kind in kinds:
        pr = cProfile.Profile(time.process_time); c0 = time.process_time()
        for k, scene, edited, original in cs:
            if k != kind: continue
            n[kind] = n.get(kind, 0) + 1
            pr.enable(); r.draw(r.prepare(original, frame, scene), edited); pr.disable()
        cpu[kind] = (time.process_time() - c0) / n[kind]
        st = pstats.Stats(pr).stats
        for (file, _, func), (_, _, _, ct, _) in st.items():
            for f, fn, name in STEPS:
                if file.endswith(f) and func == fn and ("sdn3d" in file):
                    table.setdefault(name, {})[kind] = table.get(name, {}).get(kind, 0.0) + ct / n[kind]
    lines = [f"cumulative CPU ms per edit under cProfile ({label}; lat3, fresh source state, 1 thread)", "",
             "| step | " + " | ".join(f"{k} ({n[k]})" for k in kinds) + " |", "|---|" + "---|" * len(kinds)]
    for _, _, name in STEPS:
        lines.append(f"| {name} | " + " | ".join(f"{1000 * table.get(name, {}).get(k, 0.0):.0f}" for k in kinds) + " |")
    lines.append("| CPU per edit, profiled | " + " | ".join(f"{1000 * cpu[k]:.0f}" for k in kinds) + " |")
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
