# ruff: noqa: E402, E501, E701, E702
"""lampprobe.py TREE WORLD FRAME U V: red-lamp reading of one car (full-size frame, its ground-truth mask, crop
resized to 64) in clone and rain: plain and with the air taken off (the car's darkest 5 % per channel)."""
import sys

import numpy as np
import torch
import torch.nn.functional as F
from PIL import Image

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import match_objects
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.lamps import LampCue, red_lamps

tree, world, frame = sys.argv[1:4]; u, v = float(sys.argv[4]), float(sys.argv[5])
recs = index_records(read_frames(tree))
for var in ("clone", "rain"):
    rec = recs[(world, var, int(frame))]
    sc = scene_from_frame(rec)
    gi = match_objects(sc, [(u, v)], [True])[0]
    m = sc.objects.mask[(sc.objects.instance_id == gi).nonzero()[0, 0]]
    img = torch.from_numpy(np.asarray(Image.open(rec.rgb_path).convert("RGB"))).permute(2, 0, 1).float() / 255
    ys, xs = m.nonzero(as_tuple=True); y0, y1, x0, x1 = int(ys.min()), int(ys.max()) + 1, int(xs.min()), int(xs.max()) + 1
    s = max(y1 - y0, x1 - x0)
    crop = F.interpolate(img[None, :, y0:y1, x0:x1], (64, 64), mode="bilinear"); mk = F.interpolate(m[None, None, y0:y1, x0:x1].float(), (64, 64)) > 0.5
    seen = crop * mk
    print(var, "mask px", int(m.sum()), "reading", [t.tolist() for t in red_lamps(seen, mk.float(), LampCue())])
    px = crop[0][:, mk[0, 0]].T
    q = torch.quantile(px, 0.05, dim=0); luma = px @ torch.tensor([0.299, 0.587, 0.114])
    print("   dark q05", q.tolist(), "luma q05/q95", torch.quantile(luma, torch.tensor([0.05, 0.95])).tolist())
    r, g, b = px.T; print("   max r/g among r>0.25", float((r / g.clamp(min=1e-3))[r > 0.25].max()) if (r > 0.25).any() else None)
