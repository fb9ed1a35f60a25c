# ruff: noqa: INP001, E501
"""cliprof.py SPEC OUT: cProfile of the photo stage (PhotoRenderer.draw) inside one sdn3d-edit run, as the CLI runs it
(cold: its first and only photo stage); prints the top by tottime and cumtime."""
import cProfile
import pstats
import sys

from sdn3d.cli import edit
from sdn3d.editing import appearance

spec, out = sys.argv[1], sys.argv[2]
orig = appearance.PhotoRenderer.draw


def draw(self, *args, **kwargs):
    prof = cProfile.Profile()
    prof.enable()
    try:
        return orig(self, *args, **kwargs)
    finally:
        prof.disable()
        prof.dump_stats(out)


appearance.PhotoRenderer.draw = draw
edit.main([
    "input.image=tests/data/0006_30-deg-right_00043.png",
    f"edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/{spec}.yaml",
    "run=/tmp/w38/outputs/demo/runs", "proposals=boxes", "threads=1", f"output_dir={out}.dir", "overwrite=true",
    "progress=false"])
for key in ("tottime", "cumtime"):
    pstats.Stats(out).strip_dirs().sort_stats(key).print_stats(45)
