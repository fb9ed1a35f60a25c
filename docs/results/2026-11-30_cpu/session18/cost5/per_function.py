"""Per-function ms per edit of cProfile runs of session14/cost/draw_edits.py --profile (the 14 latency edits): this
branch's runs against main's (each argument NAME=A.prof,B.prof,...: one code's runs, averaged), cumulative for the
functions this branch changed or whose callees it changed, own time for the torch and NumPy builtins it replaced,
with the ratio new/main. cProfile inflates calls, so the ratios are of the profiled runs, not of idle edits.

    python per_function.py new=N1.prof,N2.prof main=M1.prof,M2.prof
"""

import pstats
import sys

# (name, file suffix or builtin marker, which time): the changed functions and those calling the replaced builtins
ROWS = (
    ("render_photo", "transfer.py", "cum"), ("__init__", "transfer.py", "cum"), ("roty", "rotations.py", "cum"),
    ("_part_features", "transfer.py", "cum"), ("_box_floor", "transfer.py", "cum"),
    ("object_to_camera", "transforms.py", "cum"), ("_part_examples", "transfer.py", "cum"),
    ("_view_cos", "transfer.py", "cum"), ("_lab_of", "road.py", "cum"), ("_lab_of_linear", "road.py", "cum"),
    ("ray_fill", "road.py", "cum"), ("removal_vanishing_point", "road.py", "cum"), ("fill_hole", "fill.py", "cum"),
    ("thin_occluders", "occluders.py", "cum"), ("_dark_car_tyres", "transfer.py", "cum"),
    ("_pixels_of", "transfer.py", "cum"), ("_into_original", "transfer.py", "cum"),
    ("<method 'any' of 'torch._C.TensorBase' objects>", "~", "own"),
    ("<method 'nonzero' of 'torch._C.TensorBase' objects>", "~", "own"),
    ("<method 'sum' of 'torch._C.TensorBase' objects>", "~", "own"),
    ("<method 'take' of 'numpy.ndarray' objects>", "~", "own"),
    # where the replaced builtins' work went: NumPy's any, flatnonzero and count_nonzero, OpenCV's LUT
    ("_any", "numpy/_core/_methods.py", "cum"), ("flatnonzero", "numpy/_core/numeric.py", "cum"),
    ("<built-in method numpy._core._multiarray_umath.count_nonzero>", "~", "own"), ("<LUT>", "~", "own"),
)


def _matches(file: str, where: str) -> bool:
    if where == "~":  # a builtin
        return file == "~"
    if where.startswith("numpy/"):
        return file.endswith(where)
    return "sdn3d" in file and file.endswith(where)


def per_edit(paths: list[str]) -> dict[str, float]:
    totals: dict[str, float] = {}
    for path in paths:
        for (file, _, function), (_, _, own, cum, _) in pstats.Stats(path).stats.items():
            for name, where, kind in ROWS:
                if function == name and _matches(file, where):
                    totals[name] = totals.get(name, 0.0) + 1000 * (cum if kind == "cum" else own) / 14 / len(paths)
    return totals


runs = dict(arg.split("=") for arg in sys.argv[1:])
new, main = per_edit(runs["new"].split(",")), per_edit(runs["main"].split(","))
print("function (ms per edit under cProfile, mean of the runs; cum: cumulative, own: the builtin's own) | new | main"
      " | new/main")
for name, _, kind in ROWS:
    a, b = new.get(name, 0.0), main.get(name, 0.0)
    ratio = f"{a / b:.3f}" if b else "-"
    print(f"{name[:48]:48s} {kind} | {a:7.1f} | {b:7.1f} | {ratio}")
