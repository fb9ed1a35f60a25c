# ruff: noqa
"""Probe: the vanishing point and hole ray_fill gets for the real frame's black-car delete (strip spec)."""
import sys, torch
import sdn3d.editing.photo.road as R
import sdn3d.editing.photo.fill as FL
calls = []
orig = R.ray_fill
def rf(image, hole, vp, *a, **k):
    calls.append((tuple(float(v) for v in vp), int(hole.sum()), tuple(hole.shape)))
    return orig(image, hole, vp, *a, **k)
R.ray_fill = rf
FL.ray_fill = rf if hasattr(FL, "ray_fill") else None
from sdn3d.cli.edit import main
rc = main([f"input.image=tests/data/0006_30-deg-right_00043.png", "run=/tmp/s5data/lead/demo/runs", "proposals=boxes",
           f"edits={sys.argv[1]}", f"output_dir={sys.argv[2]}", "overwrite=true"])
print("rc", rc, "ray_fill calls (vp, hole px, shape):", calls)
