"""The real frame's two deletes through sdn3d-edit (tests/data, boxes, the demo's weights), one edit each, the
user's own command: OUT/car{0,1}_deleted/edited.png. Extra arguments go to sdn3d-edit (e.g. photo.ray_grain=fixed).

usage (from the repository root): real_deletes.py OUT [key=value ...]
"""

import subprocess
import sys
from pathlib import Path

import yaml

REPO = Path.cwd()
FRAME = REPO / "tests/data/0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
out = Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)
for car, iid in enumerate((12001, 12002)):
    spec = out / f"spec_{car}.yaml"
    spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "delete", "id": iid}]}))
    subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", f"input.image={FRAME}", "run=/work/final_demo/runs",
                    "proposals=boxes", f"edits={spec}", f"output_dir={out}/car{car}_deleted", *sys.argv[2:]],
                   check=True, cwd=REPO, stdout=subprocess.DEVNULL)
