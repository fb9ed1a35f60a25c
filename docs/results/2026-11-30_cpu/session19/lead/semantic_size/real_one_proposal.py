# ruff: noqa: E501
"""real_one_proposal.py (run from the repository root): the real frame of tests/data through the demo's semantic branch
as Models.from_checkpoints loads it (at its 312x96 training size); prints the proposal pixels' connected components
and writes them in magenta over the darkened frame at 624x192 (/tmp/s19data/lead/real_inst_312.png)."""
import numpy as np
import torch
from PIL import Image
from scipy import ndimage

from sdn3d.models import Models

torch.set_num_threads(1)
sem = Models.from_checkpoints(semantic="/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt").semantic
rgb = np.asarray(Image.open("tests/data/0006_30-deg-right_00043.png").convert("RGB"))
img = torch.from_numpy(rgb.copy()).permute(2, 0, 1).float() / 255
img = torch.nn.functional.interpolate(img[None], size=(192, 624), mode="bilinear", antialias=True, align_corners=False)[0]
out = sem(img)
inst = out.instance[0].numpy()
comp, n = ndimage.label(inst > 0, structure=np.ones((3, 3)))
sizes = sorted(np.bincount(comp.ravel())[1:].tolist(), reverse=True)
print("instance px", int((inst > 0).sum()), "components", n, "largest", sizes[:8])
small = (np.asarray(Image.fromarray(rgb).resize((624, 192))) * 0.5).astype(np.uint8)
small[inst > 0] = (small[inst > 0] * 0.3 + np.array([255, 0, 255]) * 0.7).astype(np.uint8)
Image.fromarray(small).save("/tmp/s19data/lead/real_inst_312.png")
