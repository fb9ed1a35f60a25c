# ruff: noqa: E501, E701, E702, B905
"""listing_figure.py MAIN_LIST BRANCH_LIST OUT.png (run from the branch's repository root): the real frame of tests/data
as `sdn3d-edit list=true proposals=semantic` lists it, main's code (MAIN_LIST: its output_dir) against the branch's
(BRANCH_LIST), and each proposal's mask and box. Rows: main's objects.png; main's proposals; the branch's objects.png;
the branch's proposals. The proposal rows are the semantic branch's instance map at the 624x192 working size (the
demo's weights as Models.from_checkpoints loads them: the network at 312x96, the map resized back), each instance
blended in its colour with its box and id; main's is the branch's code with part_separation None (main's grouping),
checked against main's listing (the same number of objects). Each row is titled."""
import json
import sys

import numpy as np
import torch
import torch.nn.functional as F
from PIL import Image, ImageDraw

from sdn3d.models import Models

torch.set_num_threads(1)
main_dir, branch_dir, out = sys.argv[1:4]
sem = Models.from_checkpoints(semantic="/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt").semantic
rgb = np.asarray(Image.open("tests/data/0006_30-deg-right_00043.png").convert("RGB"))
img = torch.from_numpy(rgb.copy()).permute(2, 0, 1).float()[None] / 255
img = F.interpolate(img, size=(192, 624), mode="bilinear", antialias=True, align_corners=False)
work = (img[0].permute(1, 2, 0).numpy() * 255).round().astype(np.uint8)
PAL = [(230, 25, 75), (60, 180, 75), (0, 130, 200), (245, 130, 48), (145, 30, 180), (70, 240, 240)]


def proposals(part_separation):
    sem.grouping["part_separation"] = part_separation
    inst = sem(img[0]).instance[0].numpy()
    pic = Image.fromarray(work); d = ImageDraw.Draw(pic); arr = np.asarray(pic).copy()
    ids = [int(i) for i in np.unique(inst) if i > 0]
    for n, i in enumerate(ids):
        m = inst == i; arr[m] = (arr[m] * 0.4 + np.array(PAL[n % len(PAL)]) * 0.6).astype(np.uint8)
    pic = Image.fromarray(arr); d = ImageDraw.Draw(pic)
    for n, i in enumerate(ids):
        vv, uu = np.nonzero(inst == i)
        d.rectangle([uu.min(), vv.min(), uu.max(), vv.max()], outline=PAL[n % len(PAL)], width=2)
        d.text((uu.min() + 3, vv.min() + 2), f"{i} ({len(uu)} px)", fill=(255, 255, 255))
    return pic, ids


def listing(path):
    objs = json.load(open(f"{path}/objects.json"))["objects"]
    pic = Image.open(f"{path}/objects.png").convert("RGB")
    return pic.resize((624, round(pic.height * 624 / pic.width))), objs


main_pic, main_ids = proposals(None)
branch_pic, branch_ids = proposals(4.0)
main_list, main_objs = listing(main_dir)
branch_list, branch_objs = listing(branch_dir)
assert len(main_objs) == len(main_ids), (len(main_objs), main_ids)
assert len(branch_objs) == len(branch_ids), (len(branch_objs), branch_ids)
rows = [(main_list, f"main (4044fb9): sdn3d-edit list=true proposals=semantic lists {len(main_objs)} object(s): " + ", ".join(f"{o['id']} box {o['box']}" for o in main_objs)),
        (main_pic, f"main's proposals at 624x192 (branch at 312x96): {len(main_ids)} instance(s), mask tinted, box drawn"),
        (branch_list, f"this branch (part_separation 4.0): lists {len(branch_objs)} object(s): " + "; ".join(f"{o['id']} box {o['box']}" for o in branch_objs)),
        (branch_pic, f"this branch's proposals at 624x192: {len(branch_ids)} instance(s), mask tinted, box drawn")]
th = 16; sheet = Image.new("RGB", (624, sum(p.height + th for p, _ in rows)), "white"); d = ImageDraw.Draw(sheet); y = 0
for p, t in rows:
    d.text((3, y + 2), t, fill="black"); sheet.paste(p, (0, y + th)); y += p.height + th
sheet.save(out); print("wrote", out, main_ids, branch_ids)
