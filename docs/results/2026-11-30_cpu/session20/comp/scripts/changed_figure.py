# ruff: noqa: E501, E701, E702, B905
"""changed_figure.py OUT.png N RAW.pt... : the N frames (of session 19 inst's raw.py files: Table 1 source frames at
312x96, the demo's weights) whose proposals change most between main's grouping (part_separation None) and the branch's
(GROUPING_DEFAULTS), by the number of pixels whose instance changes. Columns: the photo; main's proposals; the
branch's; the ground-truth Car/Van instances (oracle, for judging only). Each proposal blended in its colour; titles
give the tree and frame and the proposal count, and under main's the changed pixels' count. A colour is an instance id
(the same id has the same colour in main's and the branch's panel; the ground truth's colours are its own)."""
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic.panoptic import group_vehicles
from sdn3d.semantic.predict import GROUPING_DEFAULTS

out, n_show = sys.argv[1], int(sys.argv[2])
PAL = np.array([(230, 25, 75), (60, 180, 75), (0, 130, 200), (245, 130, 48), (145, 30, 180), (70, 240, 240), (240, 50, 230), (210, 245, 60), (250, 190, 212), (0, 128, 128)])


def group(fr, things, part):
    g = {**GROUPING_DEFAULTS, "part_separation": part}
    prob = fr["logits"].float().softmax(0)[None]
    return group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                          nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                          part_separation=part)[0][0].numpy()


def paint(photo, inst):
    arr = (photo * 0.45).astype(np.uint8)
    for k in [k for k in np.unique(inst) if k > 0]:  # colour by id: one instance, one colour in every panel
        arr[inst == k] = (photo[inst == k] * 0.3 + PAL[(k % INSTANCE_DIVISOR * 7 + k // INSTANCE_DIVISOR) % len(PAL)] * 0.7).astype(np.uint8)
    return Image.fromarray(arr).resize((inst.shape[1] * 2, inst.shape[0] * 2), Image.NEAREST)


cands = []
for path in sys.argv[3:]:
    raw = torch.load(path, weights_only=False); things = raw["things"]
    for key, fr in raw["frames"].items():
        a, b = group(fr, things, None), group(fr, things, GROUPING_DEFAULTS["part_separation"])
        cands.append((int((a != b).sum()), raw["tree"].rstrip("/").split("/")[-1], key, fr, a, b, things))
cands.sort(key=lambda c: -c[0])
rows = []
for changed, tree, key, fr, a, b, things in cands[:n_show]:
    photo = fr["image"].permute(1, 2, 0).numpy()
    gi = fr["gt_instances"].numpy(); gt = np.where((gi >= INSTANCE_DIVISOR) & np.isin(gi // INSTANCE_DIVISOR, things), gi, 0)
    na, nb, ng = (len([k for k in np.unique(x) if k > 0]) for x in (a, b, gt))
    rows.append([(Image.fromarray(photo).resize((photo.shape[1] * 2, photo.shape[0] * 2)), f"{tree} {key}"),
                 (paint(photo, a), f"main: {na} proposals ({changed} px change)"),
                 (paint(photo, b), f"branch (part_separation {GROUPING_DEFAULTS['part_separation']}): {nb} proposals"),
                 (paint(photo, gt), f"ground-truth Car/Van (oracle): {ng}")])
pw, ph = rows[0][0][0].size; th = 16
sheet = Image.new("RGB", (4 * pw, len(rows) * (ph + th)), "white"); d = ImageDraw.Draw(sheet)
for r, row in enumerate(rows):
    for c, (p, t) in enumerate(row):
        d.text((c * pw + 3, r * (ph + th) + 2), t, fill="black"); sheet.paste(p, (c * pw, r * (ph + th) + th))
sheet.save(out); print("wrote", out, [(c[0], c[1], c[2]) for c in cands[:n_show]])
