# ruff: noqa: E401, E402, E501, E701, E702, F401, I001
# eps.py EPS OUT [overrides]: sdn3d-edit on the real frame, both cars turned -90, FAN_SAME_NORMAL_DEG = EPS
import sys
import sdn3d.editing.photo.transfer as T
T.FAN_SAME_NORMAL_DEG = float(sys.argv[1])
from sdn3d.cli import edit
edit.main(["input.image=/work/main/tests/data/0006_30-deg-right_00043.png", "edits=/tmp/s32/prof/spec.yaml",
        "run=/tmp/s32/ci/outputs/demo/runs", "proposals=boxes", "threads=1", f"output_dir={sys.argv[2]}", "progress=false", *sys.argv[3:]])
