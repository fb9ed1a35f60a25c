# ruff: noqa: E501
"""delete_figure.py OUT.png INPUT.png START.png NEW.png: the real frame's black-car delete, cropped around the car, as
three labelled panels (the input, the session start's delete, this change's delete), 2x."""
import sys

import numpy as np
from PIL import Image

from sdn3d.visualize import titled_row

crop = (620, 150, 1000, 360)
titles = ("input (black car 12002)", "deleted, session start: vanishing point 66 deg off", "deleted, coherent-edge vote: 29 deg (camera 30)")
panels = [(t, np.asarray(Image.open(p).convert("RGB").crop(crop).resize((760, 420), Image.LANCZOS))) for t, p in zip(titles, sys.argv[2:5], strict=True)]
Image.fromarray(titled_row(panels)).quantize(256).save(sys.argv[1], optimize=True)
