"""Issue 31's figure: the real Virtual KITTI frame of tests/data edited through boxes around its two near cars.

    .venv/bin/python docs/results/2026-11-26_cpu/issue31/make_real_strip.py RUN OUT_DIR [IMAGE BOX ...]

RUN: the demo's output (`outputs/demo`; its geometric branch starts the fit, its textural checkpoint is loaded but
not drawn with). Each panel is one `sdn3d-edit` call (printed before it runs), `proposals=boxes`, the photo
appearance: the listing (GrabCut masks and fit IoU), then closer (zoom 1.4), turned 45 degrees, deleted, repainted
red. Writes OUT_DIR/<name>/ (the edit outputs), OUT_DIR/real_strip.png and OUT_DIR/timings.json.
"""

import json
import shlex
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.cli.edit import main as edit
from sdn3d.visualize import titled_panel

REPO = Path(__file__).resolve().parents[4]
IMAGE = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [[466, 203, 666, 333], [704, 194, 917, 305]]  # the red car and the black car, input pixels
EDITS = {"closer": ("the red car closer (zoom 1.4)", "{op: zoom, at: [565, 280], zoom: 1.4}"),
         "rotate": ("the red car turned by 45 degrees", "{op: rotate, at: [565, 280], ry_deg: 45}"),
         "delete": ("the black car deleted (road inpainted)", "{op: delete, at: [810, 260]}"),
         "red": ("the black car repainted red", "{op: recolor, at: [810, 260], color: red}")}


def main() -> None:
    run, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    objects = "objects:\n" + "".join(f"  - {{box: {b}, class: Car}}\n" for b in BOXES)
    timings = {}
    panels = []
    for name, (title, op) in [("list", ("", "")), *EDITS.items()]:
        spec = out / f"{name}.yaml"
        spec.write_text(objects + (f"ops:\n  - {op}\n" if op else ""))
        args = [f"input.image={IMAGE}", f"run={run}", f"edits={spec}", "proposals=boxes",
                f"output_dir={out / name}", "threads=2"]
        print("sdn3d-edit " + " ".join(shlex.quote(a) for a in args), flush=True)
        t0 = time.perf_counter()
        assert edit(args) == 0
        timings[name] = round(time.perf_counter() - t0, 2)
        summary = json.loads((out / name / "edit.json").read_text())
        timings[name + "_stages_ms"] = {k: round(v) for k, v in summary["timings_ms"].items()}
        if name == "list":
            panels.append(np.asarray(Image.open(out / name / "objects.png").convert("RGB")))
            panels.append(titled_panel(np.asarray(Image.open(IMAGE).convert("RGB")),
                                       "input: real Virtual KITTI frame 0006/30-deg-right/00043, 1242x375"))
        else:
            picture = np.asarray(Image.open(out / name / "edited.png").convert("RGB"))
            panels.append(titled_panel(picture, f"{title}: `{op}`"))
    width = max(p.shape[1] for p in panels)
    panels = [np.pad(p, ((0, 0), (0, width - p.shape[1]), (0, 0)), constant_values=255) for p in panels]
    height = max(p.shape[0] for p in panels)
    panels = [np.pad(p, ((0, height - p.shape[0]), (0, 0), (0, 0)), constant_values=255) for p in panels]
    gap = np.full((height, 8, 3), 255, np.uint8)
    rows = [np.concatenate([panels[i], gap, panels[i + 1]], 1) for i in range(0, len(panels), 2)]
    hgap = np.full((8, rows[0].shape[1], 3), 255, np.uint8)
    grid = np.concatenate([x for r in rows for x in (r, hgap)][:-1], 0)
    Image.fromarray(grid).save(out / "real_strip.png")
    (out / "timings.json").write_text(json.dumps(timings, indent=2))
    print(json.dumps(timings, indent=2))


if __name__ == "__main__":
    main()
