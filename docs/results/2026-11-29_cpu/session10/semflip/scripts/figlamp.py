# ruff: noqa: E402, E501, E701, E702
"""figlamp.py TREE SEM.pt OUT.png KEYS...: for each (world,var,frame,gt_id) a 4x crop of the lamp cue's window from
the photo: plain | red pixels (through the air) of the whole window in yellow, the proposal's sure mask outlined green,
the ground-truth mask (oracle) magenta."""
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import frame_photo
from sdn3d.data.vkitti1 import read_frames
from sdn3d.derender import SURE_MASK
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.lamps import LampCue, _red, through_the_air
from sdn3d.image_ops import crop_windows, mask_boxes, pixel_centre_boxes, square_crop_window

tree, cap, out = sys.argv[1:4]; want = [tuple(k.split(",")) for k in sys.argv[4:]]
recs = index_records(read_frames(tree)); rows = torch.load(cap, weights_only=False); cue = LampCue()
sel = [r for w in want for r in rows if (r["key"][0], r["key"][1], str(r["key"][2]), str(r["gt_id"])) == w]
Z = 192; canvas = Image.new("RGB", (2 * Z + 250, Z * len(sel) + 16), "white"); d = ImageDraw.Draw(canvas)
d.text((4, 2), "photo window | red (yellow) over the window, proposal sure mask green, ground-truth mask (oracle) magenta", fill="black")
def outline(a): return a & ~(np.roll(a, 1, 0) & np.roll(a, -1, 0) & np.roll(a, 1, 1) & np.roll(a, -1, 1))
for i, r in enumerate(sel):
    box = pixel_centre_boxes(mask_boxes(r["mask"][None]))[0]
    win = torch.tensor([square_crop_window(box, 0.1)], dtype=torch.float32)
    crop = frame_photo(recs[r["key"]], (312, 96)).crops(win, 64)
    lm = (crop_windows(r["mask"][None, None].float(), win, 64, "bilinear") >= SURE_MASK)[:, 0]
    gm = (crop_windows(r["gt_mask"][None, None].float(), win, 64, "bilinear") >= 0.5)[:, 0]
    allm = torch.ones_like(lm)
    red = _red(through_the_air(crop, lm, cue.clear_dark), allm, cue)[0].numpy()
    img = crop[0].permute(1, 2, 0).numpy().clip(0, 1); a = img.copy()
    a[red] = [1, 1, 0]; a[outline(lm[0].numpy())] = [0, 1, 0]; a[outline(gm[0].numpy())] = [1, 0, 1]
    y0 = 16 + i * Z
    canvas.paste(Image.fromarray((img * 255).astype(np.uint8)).resize((Z, Z), Image.NEAREST), (0, y0))
    canvas.paste(Image.fromarray((a * 255).astype(np.uint8)).resize((Z, Z), Image.NEAREST), (Z, y0))
    d.text((2 * Z + 6, y0 + 6), f"{r['key'][0]} {r['key'][1]} f{r['key'][2]}\nid {r['gt_id']}\nmask IoU {r['iou']:.2f}\nsure px {int(lm.sum())}", fill="black")
canvas.save(out); print(len(sel))
