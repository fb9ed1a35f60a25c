"""join624.py: which of the joined tuning frames (312x96) also join at 624x192 (sdn3d-edit's size in the 3 s goal),
de-rendered as an edit call does (the image file resized, predicted proposals, FitSettings())."""
import numpy as np
import torch
from PIL import Image

from sdn3d.derender import derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.math3d.camera import Intrinsics
from sdn3d.models import Models

torch.set_num_threads(1)
R = "/tmp/s28/demo2/outputs/demo/runs"
models = Models.from_checkpoints(semantic=f"{R}/semantic/checkpoints/inference.pt",
                                 geometric=f"{R}/geometric/checkpoints/inference.pt")
intr = Intrinsics(725.0, 725.0, 620.5, 187.0, 1242, 375).resized(624, 192)
for seed, f in [(11, "0001/clone/00034"), (11, "0001/rain/00034"), (37, "0001/rain/00037")]:
    p = f"/tmp/s28/merge40/trees/t1_{seed}/vkitti_1.3.1_rgb/{f}.png"
    im = Image.open(p).convert("RGB").resize((624, 192), Image.BICUBIC)
    image = torch.from_numpy(np.asarray(im)).permute(2, 0, 1).float() / 255
    s = derender(image, intr, models, "semantic", classes="vkitti", fit=FitSettings())
    print(seed, f, len(s.objects.instance_id), [r["joined_from"] for r in s.meta["fits"] if r["joined_from"]],
          flush=True)
