# ruff: noqa: E402, E501, E701, E702, E731
"""crops.png (tuning tree val13 only): for cars whose end the two crops decide differently, what the geometric branch
and its lamp cue see: the working image's crop (312x96) with its mask, the photo's crop (the frame as stored,
624x192) with the same mask, and the lamp pixels the cue counts in the photo's crop (red: inside the crop pixels surely
on the car, yellow: red pixels of the mask's edge the cue no longer counts). Each row: the car in the working image
(its crop window outlined; its world, instance and visible pixels at 312x96), then the crops titled with the branch's
yaw error (degrees) from each (ground-truth masks; before: working crops, whole mask; after: photo crops, sure mask).

    python crops_picture.py DATA OLD.json NEW.json OUT.png
"""
import json
import sys

import numpy as np
import torch
from PIL import Image

from sdn3d.cli._config import synth_data_source
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import frame_photo, ground_truth, scene_from_frame
from sdn3d.data.sources import load_split
from sdn3d.derender import SURE_MASK
from sdn3d.geometric.lamps import LampCue
from sdn3d.image_ops import crop_windows, square_crop_window
from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.visualize import titled_row

data, old_p, new_p, out = sys.argv[1:5]
rows_of = lambda p: {(r["frame"], r["id"]): r for r in json.load(open(p))["objects"]["branch, oracle: ground-truth masks"]}
old, new = rows_of(old_p), rows_of(new_p)
changed = [k for k in old if (old[k]["yaw_deg"] > 90) != (new[k]["yaw_deg"] > 90)][:8]
records = {r.key: r for p in ("train", "val", "test") for r in load_split(synth_data_source(data), p)}
cue, size, S = LampCue(), (312, 96), 112
grid = []


def image_context(image, w):
    """The working image around the window (three times its side), the window outlined in white."""
    left, top, side = (float(v) for v in w[0])
    big = torch.tensor([[left - side, top - side, 3 * side]])
    ctx = crop_windows(image, big, S, "bilinear")[0]
    lo, hi = S // 3, 2 * S // 3
    ctx[:, lo, lo:hi] = ctx[:, hi, lo:hi] = 1.0
    ctx[:, lo:hi, lo] = ctx[:, lo:hi, hi] = 1.0
    return ctx


for frame, iid in changed:
    rec = records[frame]
    gt, truth = ground_truth(rec, size), scene_from_frame(rec, size)
    image = load_frame(rec, size, semantic=False, instances=False).image
    photo = frame_photo(rec, size)
    r = int((truth.objects.instance_id == iid).nonzero()[0])
    w = torch.tensor([square_crop_window(gt.boxes[iid % INSTANCE_DIVISOR], 0.1)], dtype=torch.float32)
    mk = truth.objects.mask[r][None, None].float()
    m = crop_windows(mk, w, S, "nearest")[0, 0] > 0.5
    sure = crop_windows(mk, w, S, "bilinear")[0, 0] >= SURE_MASK
    a = crop_windows(image, w, S, "bilinear")[0]
    b = photo.crops(w, S)[0]
    red = (b[0] > cue.red_min) & (b[0] > cue.ratio * b[1]) & (b[0] > cue.ratio * b[2])
    lamps = b * m
    lamps = torch.where((red & sure)[None], torch.tensor([1.0, 0, 0])[:, None, None], lamps * 0.5)
    lamps = torch.where((red & m & ~sure)[None], torch.tensor([1.0, 1.0, 0])[:, None, None], lamps)
    to = lambda t: (t.permute(1, 2, 0).clamp(0, 1).numpy() * 255).astype(np.uint8)
    px = old[(frame, iid)]["pixels"]
    before, after = old[(frame, iid)]["yaw_deg"], new[(frame, iid)]["yaw_deg"]
    grid.append(titled_row([(f"{frame.split('/')[1]} car {iid % 1000}, {px} px", to(image_context(image, w))),
                            (f"working crop: {before:.0f} deg", to(a * m)), (f"photo crop: {after:.0f} deg", to(b * m)),
                            ("lamps: counted / edge", to(lamps))], font_size=11))
width = max(g.shape[1] for g in grid)
pic = np.concatenate([np.pad(g, ((0, 4), (0, width - g.shape[1]), (0, 0)), constant_values=255) for g in grid])
Image.fromarray(pic).quantize(128).save(out, optimize=True)
print(out, pic.shape, len(changed))
