# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
import cProfile, os, pstats, sys
import sdn3d.editing.photo.transfer as T
from sdn3d.cli.edit import main
pr = cProfile.Profile()
orig = T._rays_with_effects
def wrapped(*a, **k):
    pr.enable()
    try: return orig(*a, **k)
    finally: pr.disable()
T._rays_with_effects = wrapped
try:
    main(["input.image=tests/data/0006_30-deg-right_00043.png", f"edits=/work/notes/s35/photo/{os.environ.get('SPEC','t1')}.yaml",
          "run=/tmp/w35/outputs/demo/runs", "proposals=boxes", "threads=1", "output_dir=/tmp/s35_prof3", "overwrite=true", "progress=false"])
except SystemExit:
    pass
pstats.Stats(pr).sort_stats("tottime").print_stats(25)
