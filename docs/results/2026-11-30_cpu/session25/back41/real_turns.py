"""The real Virtual KITTI frame of tests/data, each car turned 45, 90 and 180 degrees through README's boxes, on
main's code and the branch's (one ``sdn3d-edit`` per edit, the user's command; session 21's demo weights w0;
session 22 side2's script, panels titled with the codes' commits):

    /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session23/front/real_turns.py RUN_DIR OUT_DIR \\
        MAIN_SRC BRANCH_SRC MAIN_LABEL BRANCH_LABEL

Writes OUT_DIR/real_turns_main_vs_branch.png (one row per car and code, each panel titled with car, edit and code,
crops around the car), OUT_DIR/{main,branch}/car*_turned_*/ (the edits' outputs, ``maps/photo_source.png``
included) and prints, per edit, the car's source shares and whether main's and the branch's pictures are identical.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import yaml
from PIL import Image

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
TURNS = (45, 90, 180)


def main() -> int:
    from sdn3d.visualize import titled_row

    run, out = Path(sys.argv[1]), Path(sys.argv[2])
    codes = {"main": Path(sys.argv[3]), "branch": Path(sys.argv[4])}
    label = {"main": sys.argv[5], "branch": sys.argv[6]}
    out.mkdir(parents=True, exist_ok=True)
    rows, lines = [], []
    for car, (iid, box) in enumerate(zip((12001, 12002), BOXES, strict=True)):
        x0, y0, x1, y1 = box["box"]
        crop = (max(0, x0 - 120), max(0, y0 - 60), min(1242, x1 + 120), min(375, y1 + 40))
        pictures: dict[str, list[np.ndarray]] = {}
        for code, src in codes.items():
            panels = []
            for deg in TURNS:
                target = out / code / f"car{car}_turned_{deg}"
                spec = out / code / f"spec_car{car}_{deg}.yaml"
                spec.parent.mkdir(parents=True, exist_ok=True)
                spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [{"op": "rotate", "ry_deg": deg, "id": iid}]}))
                env = {**os.environ, "PYTHONPATH": str(src / "src"), "OMP_NUM_THREADS": "1"}
                subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", f"input.image={FRAME}", f"run={run}",
                                "proposals=boxes", f"edits={spec}", f"output_dir={target}"], check=True, cwd=src,
                               env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                image = np.asarray(Image.open(target / "edited.png").convert("RGB"))
                panels.append((f"car {iid} turned {deg}: {label[code]}", image[crop[1]:crop[3], crop[0]:crop[2]]))
                shares = json.loads((target / "edit.json").read_text())["photo"]["objects"][str(iid)]
                lines.append(f"car {iid} turned {deg} {code}: {shares}")
            pictures[code] = [p[1] for p in panels]
            rows.append(titled_row(panels))
        for deg, a, b in zip(TURNS, pictures["main"], pictures["branch"], strict=True):
            lines.append(f"car {iid} turned {deg}: main and branch identical: {bool(np.array_equal(a, b))}, "
                         f"pixels differing: {int((a != b).any(-1).sum())}")
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).save(out / "real_turns_main_vs_branch.png")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
