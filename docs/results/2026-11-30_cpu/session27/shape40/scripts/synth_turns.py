"""synth_turns.py OUT.png MAIN_CODE BRANCH_CODE: two tuning-tree cars (predicted proposals, w0) listed and turned by 90
degrees by each code's ``sdn3d-edit`` (the user's own command, 312x96 working size): one panel per code and edit,
titled with the code, the op and the template listed; the truth's template in the row title (an oracle, only to
score). Outputs of each run under OUT's folder (work/; a run whose outputs are there is not run again).
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

W0 = "/tmp/s21data/demo/out"
# (tree, frame, true box at 312x96, truth's template, what changed) from tables/tuning_changed_cars.txt
CASES = [("/tmp/s25data/pose40/trees/t1_33", "vkitti1/0001/rain/00045", (50.8, 50.2, 95.8, 70.8), "hatchback"),
         ("/tmp/s21data/trees/t1_31", "vkitti1/0002/rain/00026", (177.2, 50.2, 212.2, 72.2), "hatchback")]


def run(code: str, tree: str, frame: str, out: Path, spec: dict | None) -> Path:
    if (out / ("objects.json" if spec is None else "edited.png")).exists():  # run before: its outputs are kept
        return out
    args = [sys.executable, "-m", "sdn3d.cli.edit", "data=synth", f"data.root={tree}", f"input.frame={frame}",
            "image_size=[312,96]", f"run={W0}", "threads=1", f"output_dir={out}"]
    if spec is None:
        args.append("list=true")
    else:
        (out.parent / f"{out.name}.yaml").write_text(yaml.safe_dump(spec))
        args.append(f"edits={out.parent / (out.name + '.yaml')}")
    env = {**os.environ, "PYTHONPATH": f"{code}/src", "OMP_NUM_THREADS": "1"}
    subprocess.run(args, check=True, cwd=code, env=env, stdout=subprocess.DEVNULL)
    return out


def overlap(a, b) -> float:
    w = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    h = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    return w * h


def main() -> int:
    from sdn3d.visualize import titled_row

    out, codes = Path(sys.argv[1]), {"main": sys.argv[2], "branch": sys.argv[3]}
    work = out.parent / "work"
    work.mkdir(parents=True, exist_ok=True)
    rows = []
    for c, (tree, frame, box, truth) in enumerate(CASES):
        panels = []
        for name, code in codes.items():
            listed = run(code, tree, frame, work / f"case{c}_{name}_list", None)
            objects = json.loads((listed / "objects.json").read_text())["objects"]
            scale = json.loads((listed / "objects.json").read_text())["input_size"][0] / 312
            big = [v * scale for v in box]
            obj = max(objects, key=lambda o: overlap(o["box"], big))
            turned = run(code, tree, frame, work / f"case{c}_{name}_turn90",
                         {"ops": [{"op": "rotate", "id": obj["id"], "ry_deg": 90}]})
            pad = 30 * scale / 2
            crop = (max(0, big[0] - pad), max(0, big[1] - pad), big[2] + pad, big[3] + pad)
            for title, picture in ((f"{name}: listed, {obj['template']}", listed / "objects.png"),
                                   (f"{name}: turned 90, {obj['template']}", turned / "edited.png")):
                image = Image.open(picture).convert("RGB")
                crop_box = tuple(int(round(v)) for v in (crop[0], crop[1], min(image.width, crop[2]),
                                                          min(image.height, crop[3])))
                image = image.crop(crop_box)
                image = image.resize((image.width * 2, image.height * 2), Image.NEAREST)
                panels.append((f"{Path(tree).name} {frame[13:]} {title} (truth {truth})", np.asarray(image)))
        rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    Image.fromarray(grid).quantize(256).save(out)  # a palette keeps it under ~400 KB
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
