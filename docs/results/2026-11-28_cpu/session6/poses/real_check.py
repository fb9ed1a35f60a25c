# ruff: noqa: E402, E501, E701, E702
"""The real Virtual KITTI frame of tests/data (1242x375) through two boxes, one per car (as session 4/5's
real_strip.py): what ``sdn3d-edit`` lists for each car (yaw, template, fit IoU), with the code before this session
(SRC_OLD, an export of 5426919's src) and now, at sdn3d-edit's default working size (624x192) and the demo's (312x96).

    python real_check.py OUT.json RUN_DIR [RUN_DIR ...]   (env SRC_OLD, SRC_NEW: the two src folders)
"""
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
out, runs = sys.argv[1], sys.argv[2:]
rows = []
with tempfile.TemporaryDirectory() as tmp:
    spec = Path(tmp) / "spec.yaml"
    spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": []}))
    for run in runs:
        for size in (None, (312, 96)):
            for code in ("old", "new"):
                target = Path(tmp) / f"{code}_{len(rows)}"
                env = {**os.environ, "PYTHONPATH": os.environ[f"SRC_{code.upper()}"], "OMP_NUM_THREADS": "1"}
                extra = [] if size is None else [f"image_size=[{size[0]},{size[1]}]"]
                subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", f"input.image={FRAME}", f"run={run}",
                                "proposals=boxes", f"edits={spec}", f"output_dir={target}", *extra], check=True,
                               cwd=REPO, env=env, stdout=subprocess.DEVNULL)
                listing = json.loads((target / "objects.json").read_text())
                for o in listing["objects"]:
                    rows.append({"run": run, "working_size": listing["working_size"], "code": code, "id": o["id"],
                                 "yaw_deg": o["yaw_deg"], "template": o["template"], "fit_iou": o.get("fit_iou"),
                                 "distance_m": o["distance_m"], "pose_from": o.get("pose_from")})
                    print(rows[-1], flush=True)
Path(out).write_text(json.dumps(rows, indent=1))
