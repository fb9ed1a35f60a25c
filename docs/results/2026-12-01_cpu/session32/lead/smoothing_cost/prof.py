# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
# profile sdn3d-edit on the real frame, both cars turned -90; argv: OUT [overrides]
import cProfile, pstats, sys, time
from sdn3d.cli import edit
OUT = sys.argv[1]
args = ["input.image=/work/main/tests/data/0006_30-deg-right_00043.png", "edits=/tmp/s32/prof/spec.yaml",
        "run=/tmp/s32/ci/outputs/demo/runs", "proposals=boxes", "threads=1", f"output_dir={OUT}", "progress=false", *sys.argv[2:]]
pr = cProfile.Profile(); pr.enable(); rc = edit.main(args); pr.disable()
st = pstats.Stats(pr); st.sort_stats("cumulative")
st.print_stats("transfer.py|_nearest|cdist|topk|photo", 40)
