# ruff: noqa: E501, E701, E702
"""order_figure.py OUT.png N COMMIT RAW.pt... (run from the repository root): the N frames (session 19 inst's raw.py
files: Table 1 source frames at 312x96, the demo's weights) whose proposals differ most, by pixels, between comp's
order (the grouping at COMMIT, e6337c1: the part rule before the 2-means split) and comp2's (installed: the split
first, then the part rule), both with GROUPING_DEFAULTS. Columns: the photo; main's grouping (part_separation None);
comp's order; comp2's order; the ground-truth Car/Van instances (oracle, for judging only). A colour is an instance id
(the same in the three grouping panels); titles give the tree, frame, proposal counts and changed pixels."""
import importlib.util
import subprocess
import sys
import tempfile

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.labels import INSTANCE_DIVISOR
from sdn3d.semantic import panoptic as installed
from sdn3d.semantic.predict import GROUPING_DEFAULTS

out, n_show, commit, paths = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4:]
with tempfile.NamedTemporaryFile("w", suffix=".py") as f:
    f.write(subprocess.run(["git", "show", f"{commit}:src/sdn3d/semantic/panoptic.py"], capture_output=True, text=True, check=True).stdout); f.flush()
    spec = importlib.util.spec_from_file_location("panoptic_at_commit", f.name); old = sys.modules["panoptic_at_commit"] = importlib.util.module_from_spec(spec); spec.loader.exec_module(old)
COLOURS = np.array([(230, 25, 75), (60, 180, 75), (0, 130, 200), (245, 130, 48), (145, 30, 180), (70, 240, 240), (240, 50, 230), (210, 245, 60), (250, 190, 212), (0, 128, 128)])


def group(module, fr, things, part):
    g = GROUPING_DEFAULTS; prob = fr["logits"].float().softmax(0)[None]
    return module.group_vehicles(prob.argmax(1), prob, fr["center"][None], fr["offset"][None], things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                                 nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                                 part_separation=part)[0][0].numpy()


def tint(photo, inst):
    arr = (photo * 0.45).astype(np.uint8)
    for k in [k for k in np.unique(inst) if k > 0]:
        arr[inst == k] = (photo[inst == k] * 0.3 + COLOURS[(k % INSTANCE_DIVISOR * 7 + k // INSTANCE_DIVISOR) % len(COLOURS)] * 0.7).astype(np.uint8)
    return Image.fromarray(arr).resize((inst.shape[1] * 2, inst.shape[0] * 2), Image.NEAREST)


def count(x): return len([k for k in np.unique(x) if k > 0])


found = []
for path in paths:
    raw = torch.load(path, weights_only=False); things = raw["things"]
    for key, fr in raw["frames"].items():
        a, b = group(old, fr, things, GROUPING_DEFAULTS["part_separation"]), group(installed, fr, things, GROUPING_DEFAULTS["part_separation"])
        if (a != b).any(): found.append((int((a != b).sum()), raw["tree"].rstrip("/").split("/")[-1], key, fr, things, a, b))
found.sort(key=lambda c: -c[0])
rows = []
for changed, tree, key, fr, things, a, b in found[:n_show]:
    photo = fr["image"].permute(1, 2, 0).numpy(); m = group(installed, fr, things, None)
    gi = fr["gt_instances"].numpy(); gt = np.where((gi >= INSTANCE_DIVISOR) & np.isin(gi // INSTANCE_DIVISOR, things), gi, 0)
    rows.append([(Image.fromarray(photo).resize((photo.shape[1] * 2, photo.shape[0] * 2)), f"{tree} {key}"),
                 (tint(photo, m), f"main: {count(m)} proposals"),
                 (tint(photo, a), f"comp, part rule first: {count(a)}"),
                 (tint(photo, b), f"comp2, split first: {count(b)} ({changed} px differ)"),
                 (tint(photo, gt), f"ground-truth Car/Van (oracle): {count(gt)}")])
pw, ph = rows[0][0][0].size; th = 16
sheet = Image.new("RGB", (5 * pw, len(rows) * (ph + th)), "white"); d = ImageDraw.Draw(sheet)
for r, row in enumerate(rows):
    for c, (p, t) in enumerate(row):
        d.text((c * pw + 3, r * (ph + th) + 2), t, fill="black"); sheet.paste(p, (c * pw, r * (ph + th) + th))
sheet.save(out); print("wrote", out, len(found), "frames differ;", [(c[0], c[1], c[2]) for c in found[:n_show]])
