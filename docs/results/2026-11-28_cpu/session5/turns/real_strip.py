"""The real Virtual KITTI frame of tests/data edited through boxes: each car turned 45, 90 and 180 degrees, in the
default photo appearance, with a demo's weights (issue 41's turns strip).

    .venv/bin/python docs/results/2026-11-28_cpu/session5/turns/real_strip.py RUN_DIR OUT_DIR [OVERRIDE ...]

Runs one ``sdn3d-edit`` per edit (the user's own command, OVERRIDEs appended) and writes OUT_DIR/real_strip.png: one
row per car, each panel titled with its edit and the yaw it ends at (the fitted yaw plus the turn; the listing's
template), plus the listing's fit records. Session 4 copy of ``issue40_41/real_strip.py`` (titles with the yaw,
overrides, 2/3 size and 256 colours for the records); session 5: the turns only.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import yaml
from PIL import Image

REPO = Path(__file__).resolve().parents[5]
FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]
EDITS = [("listed", None), ("turned 45", {"op": "rotate", "ry_deg": 45}), ("turned 90", {"op": "rotate", "ry_deg": 90}),
         ("turned 180", {"op": "rotate", "ry_deg": 180})]


def main() -> int:
    from sdn3d.visualize import titled_row

    run, out, overrides = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3:]
    out.mkdir(parents=True, exist_ok=True)
    rows, records = [], {}
    for car, (iid, box) in enumerate(zip((12001, 12002), BOXES, strict=True)):
        x0, y0, x1, y1 = box["box"]
        pad = 60
        crop = (max(0, x0 - pad), max(0, y0 - pad), min(1242, x1 + pad), min(375, y1 + pad))
        panels = []
        for title, op in EDITS:
            spec = out / f"spec_{car}_{title.replace(' ', '_')}.yaml"
            spec.write_text(yaml.safe_dump({"objects": BOXES, "ops": [] if op is None else [{**op, "id": iid}]}))
            target = out / f"car{car}_{title.replace(' ', '_')}"
            subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", f"input.image={FRAME}", f"run={run}",
                            "proposals=boxes", f"edits={spec}", f"output_dir={target}", *overrides], check=True,
                           cwd=REPO,
                           stdout=subprocess.DEVNULL)
            picture = target / ("objects.png" if op is None else "edited.png")
            if op is None:
                records[iid] = json.loads((target / "objects.json").read_text())
            listed = next(o for o in records[iid]["objects"] if o["id"] == iid)
            yaw = listed["yaw_deg"] + (op or {}).get("ry_deg", 0)
            yaw = (yaw + 180) % 360 - 180
            label = f"{iid}: {title}, yaw {yaw:.0f}" + (f" {listed['template']}" if op is None else "")
            image = Image.open(picture).convert("RGB").crop(crop)
            panels.append((label, np.asarray(image)))
        rows.append(titled_row(panels))
    width = max(r.shape[1] for r in rows)
    grid = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
    picture = Image.fromarray(grid)
    picture = picture.resize((picture.width * 2 // 3, picture.height * 2 // 3), Image.LANCZOS)
    picture.quantize(256).save(out / "real_strip.png", optimize=True)
    (out / "listing.json").write_text(json.dumps(records, indent=1))
    print(out / "real_strip.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
