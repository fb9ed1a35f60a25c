# ruff: noqa: E402, E501, E701, E702  (a one-off record script, kept as it ran)
"""Profile one derender(boxes) call of fit_cost's dense frame: cProfile (top functions) + stage times."""

import cProfile
import io
import pstats
import sys
import time
from pathlib import Path

import torch

sys.path.insert(0, "benchmarks")
torch.set_num_threads(1)
import fit_cost
import numpy as np
from PIL import Image

from sdn3d.derender import BoxPrompts, derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.math3d.camera import VKITTI_INTRINSICS
from sdn3d.models import Models

root = Path(sys.argv[1])
n = int(sys.argv[2]) if len(sys.argv) > 2 else 10
kv = dict(a.split("=", 1) for a in sys.argv[3:])
path, boxes = fit_cost._dense_frame(root)
boxes = boxes[:n]
image = torch.from_numpy(np.array(Image.open(path).convert("RGB"))).permute(2, 0, 1).float() / 255
intr = VKITTI_INTRINSICS.resized(624, 192)
fs = FitSettings(**{k: type(getattr(FitSettings(), k))(v) for k, v in kv.items()})
prompts = BoxPrompts(torch.tensor(boxes, dtype=torch.float32), tuple("Car" for _ in boxes), fit=fs)
models = Models.from_checkpoints(geometric="/tmp/h5runs/big_mb40/checkpoints/inference.pt")
derender(image, intr, models, "boxes", boxes=prompts, classes="vkitti")
pr = cProfile.Profile()
t0 = time.process_time()
pr.enable()
scene = derender(image, intr, models, "boxes", boxes=prompts, classes="vkitti")
pr.disable()
print("cpu", time.process_time() - t0)
s = io.StringIO()
st = pstats.Stats(pr, stream=s)
st.sort_stats("cumulative").print_stats(45)
st.sort_stats("tottime").print_stats(30)
print(s.getvalue())
print([None if r.iou is None else round(r.iou, 3) for r in scene.meta["boxes"]])
