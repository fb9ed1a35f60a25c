# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
import cProfile, pstats, sys
from sdn3d.cli.edit import main
sys.argv = ["sdn3d-edit", "input.image=tests/data/0006_30-deg-right_00043.png", "edits=/work/notes/s34/photo/t1.yaml",
            "run=/tmp/s34/demo/outputs/demo/runs", "proposals=boxes", "threads=1", "output_dir=/tmp/s34/ph_prof",
            "overwrite=true", "progress=false"]
pr = cProfile.Profile(); pr.enable()
try:
    main(sys.argv[1:])
except SystemExit:
    pass
pr.disable()
pstats.Stats(pr).sort_stats("cumulative").print_stats("editing/photo|render/|native", 45)
