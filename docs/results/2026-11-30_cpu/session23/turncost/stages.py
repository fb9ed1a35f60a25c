# ruff: noqa: E402
"""Where a photo edit's time goes, by stage, without a profiler: module functions of the photo path are wrapped in
wall-clock timers (perf_counter; a nested call's time is also its caller's), then session 14's draw_edits.py runs
(its arguments follow). Prints ms per edit of the drawn edits (the warm-up excluded) and each stage's share of
``render_photo``; ``--json OUT`` keeps the totals.

    python stages.py [--json OUT] TREE OUT [draw_edits args...]

(session 20 tcost's stages.py with session 23's names; run from the repository root with PYTHONPATH=CODE/src)
"""

import json
import runpy
import sys
import time
from collections import defaultdict

import sdn3d.editing.photo.fill as fill
import sdn3d.editing.photo.road as road
import sdn3d.editing.photo.transfer as transfer

DRAW_EDITS = "docs/results/2026-11-29_cpu/session14/cost/draw_edits.py"
# session 20's list, with session 23's names of the fill's parts; a name is wrapped in every module that has it
# (the module's own calls and the importers' calls, each counted once)
NAMES = ["render_photo", "_rasterize", "_part_map", "_raster_ids", "_draw", "_paste_near_views",
         "_remove_with_effects", "_rays_with_effects", "_surface_points", "_visible", "_part_examples",
         "_part_colors", "_nearest_examples", "_reflect_part_colors", "_reflection_strength",
         "_from_real_wheels", "_sample", "_outline_growth", "_dark_car_tyres", "seen_through_the_air",
         "_clear_air", "_pyramid", "thin_occluders", "compose_instances", "posed_meshes", "upsample_ids",
         "_erode_ids", "removal_vanishing_point", "vacated_hole", "_grow", "_into_original", "_in_silhouette",
         "_on_real_wheel", "_wheel_faces", "_greenhouse_glass", "fill_hole", "removal_guides", "leftover_pieces",
         "shadow_pieces", "inpaint", "_shadow_context", "road_colours", "image_vanishing_point",
         "ray_fill", "shadowed_road", "road_haze", "_trace", "_matched_weight", "_along", "_normalised_blur",
         "_coarse_blur", "_masked_median", "_mirrored", "_continued_verge", "_source_light", "_recolor",
         "_contact_shadow", "_effects_regions", "_ground_rows"]
WRAPPED = {m: [n for n in NAMES if callable(getattr(m, n, None))] for m in (transfer, fill, road)}
CLASS_WRAPPED = [(transfer.PhotoSource, "__init__"), (road.PictureLab, "_convert"), (road.PictureLab, "__init__")]
total: dict[str, float] = defaultdict(float)
calls: dict[str, int] = defaultdict(int)


def timed(name, fn):
    def wrapper(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            total[name] += time.perf_counter() - t0
            calls[name] += 1
    return wrapper


for module, names in WRAPPED.items():
    for name in names:
        setattr(module, name, timed(name, getattr(module, name)))
for cls, name in CLASS_WRAPPED:
    setattr(cls, name, timed(f"{cls.__name__}.{name}", getattr(cls, name)))

args = sys.argv[1:]
out_json = None
if args[0] == "--json":
    out_json, args = args[1], args[2:]
# The warm-up edit is drawn before the timed ones: the totals restart when its draw returns; each edit's totals are
# kept when its draw returns (prepare + draw of a fresh source).
import sdn3d.editing.appearance as appearance

per_edit: list[dict[str, float]] = []
original_draw = appearance.PhotoRenderer.draw


def counted_draw(self, *a, **k):
    out = original_draw(self, *a, **k)
    per_edit.append(dict(total))
    total.clear()
    calls.clear()
    return out


appearance.PhotoRenderer.draw = counted_draw
sys.argv = [DRAW_EDITS, *args]
runpy.run_path(DRAW_EDITS, run_name="__main__")
edits = per_edit[1:]
names = sorted({n for e in edits for n in e}, key=lambda n: -sum(e.get(n, 0.0) for e in edits))
whole = sum(e.get("render_photo", 0.0) + e.get("PhotoSource.__init__", 0.0) for e in edits)
print(f"{len(edits)} edits; ms per edit (wall, mean), share of prepare + render_photo")
for n in names:
    ms = 1000 * sum(e.get(n, 0.0) for e in edits) / len(edits)
    share = 100 * sum(e.get(n, 0.0) for e in edits) / whole
    print(f"  {ms:8.1f} ms {share:5.1f} %  {n}")
if out_json:
    with open(out_json, "w") as fh:
        json.dump(edits, fh, indent=1)
