# ruff: noqa: E402, E501, E701, E702
"""fig_band.py TREE BEFORE.pt AFTER.pt OUT.png KEYS...: per car (world,variation,frame,gt_id) the lamp cue's window
(4x): the photo | the red pixels (yellow) over the window, the semantic proposal's sure mask (green), the band under
it (cyan), the ground-truth mask (oracle, magenta) | the fitted yaw's error before (main) and after (this branch)."""
import math
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
from sdn3d.proposal_fit import unsure_below

tree, before, after, out = sys.argv[1:5]; want = [tuple(k.split(",")) for k in sys.argv[5:]]
recs = index_records(read_frames(tree)); cue = LampCue()
def key(r): return (r["key"][0], r["key"][1], str(r["key"][2]), str(r["gt_id"]))
B = {key(r): r for r in torch.load(before, weights_only=False)}; A = {key(r): r for r in torch.load(after, weights_only=False)}
def err(r): return abs(math.degrees(math.atan2(math.sin(r["fit_ry"] - r["true_ry"]), math.cos(r["fit_ry"] - r["true_ry"]))))
def outline(a): return a & ~(np.roll(a, 1, 0) & np.roll(a, -1, 0) & np.roll(a, 1, 1) & np.roll(a, -1, 1))
Z = 160; canvas = Image.new("RGB", (2 * Z + 230, Z * len(want) + 30), "white"); d = ImageDraw.Draw(canvas)
d.text((4, 2), "photo window | red pixels of mask + band (yellow), semantic mask (green), band under it (cyan),\nground-truth mask (oracle, magenta) | yaw error of the fit: main -> this branch", fill="black")
for i, w in enumerate(want):
    r = B[w]; m = r["mask"]; others = (r["all_masks"].sum(0) - m.long()) > 0
    band = unsure_below(m[None])[0] & ~others
    box = pixel_centre_boxes(mask_boxes(m[None]))[0]
    win = torch.tensor([square_crop_window(box, 0.1)], dtype=torch.float32)
    crop = frame_photo(recs[r["key"]], (312, 96)).crops(win, 64)
    def cw(x, th, win=win): return (crop_windows(x[None, None].float(), win, 64, "bilinear") >= th)[0, 0]
    lm, tl, gm = cw(m, SURE_MASK), cw(m | band, SURE_MASK), cw(r["gt_mask"], 0.5)
    red = _red(through_the_air(crop, tl[None], cue.clear_dark), tl[None], cue)[0].numpy()
    img = crop[0].permute(1, 2, 0).numpy().clip(0, 1); a = img.copy()
    a[red] = [1, 1, 0]; a[outline(tl.numpy()) & ~lm.numpy()] = [0, 1, 1]; a[outline(lm.numpy())] = [0, 1, 0]; a[outline(gm.numpy())] = [1, 0, 1]
    y0 = 30 + i * Z
    canvas.paste(Image.fromarray((img * 255).astype(np.uint8)).resize((Z, Z), Image.NEAREST), (0, y0))
    canvas.paste(Image.fromarray((a * 255).astype(np.uint8)).resize((Z, Z), Image.NEAREST), (Z, y0))
    d.text((2 * Z + 6, y0 + 6), f"world {w[0]} {w[1]} frame {w[2]}\ncar {w[3]}, mask IoU {r['iou']:.2f}\nyaw error {err(r):.0f} -> {err(A[w]):.0f} deg" if w in A else "", fill="black")
canvas.save(out, optimize=True); print(out)
