# ruff: noqa: E402, E501, E701, E702
"""real_312.png: sdn3d-edit's objects.png of the real frame (tests/data, a box per car, the s5 demo's weights,
image_size=[312,96]) with the code before this session and now, side by side, titled with each car's listed yaw.

    python real_picture.py OLD_DIR NEW_DIR OUT.png   (each DIR: an sdn3d-edit output_dir with objects.png/json)
"""
import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

rows = []
for name, d in (("before (working image's crops)", Path(sys.argv[1])), ("now (the photo's crops)", Path(sys.argv[2]))):
    listing = json.loads((d / "objects.json").read_text())
    yaws = ", ".join(f"{o['id']}: yaw {o['yaw_deg']:.0f} {o['template']} IoU {o['fit_iou']:.2f}" for o in listing["objects"])
    image = np.asarray(Image.open(d / "objects.png").convert("RGB").crop((380, 150, 1000, 360)))
    rows.append(titled_row([(f"{name}; {yaws}", image)], font_size=14))
width = max(r.shape[1] for r in rows)
pic = np.concatenate([np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows])
Image.fromarray(pic).quantize(256).save(sys.argv[3], optimize=True)
print(sys.argv[3], pic.shape)
