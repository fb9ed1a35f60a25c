# ruff: noqa: E402, E501, E701, E702
"""Counterfactual deletes (oracle: ground-truth geometry, scene_from_frame), session 7 haze: PSNR on the vacated region
+ shadow band per photo-settings variant, and road_haze's fog signals (hazesig.py) of the variant named SIG.
usage: cf_diag.py ROOT OUT.json SIG VARIANT...   VARIANT = name[:key=val,...] (PhotoSettings fields)"""
import json
import math
import sys
import time
from pathlib import Path

import torch
import yaml

sys.path.insert(0, str(Path(__file__).parent))
import hazesig

import sdn3d.editing.photo.transfer as T
from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings

torch.set_num_threads(1)
root, out_path, sig, specs = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3], sys.argv[4:]
index = load_pairs(root); size = index.image_size
recs = {(r.world, r.variation, r.frame): r for r in read_frames(root, worlds=sorted({p.world for p in index.pairs}))}
frame = PixelFrame(size, size)
LOG = []
hazesig.install(LOG)


def psnr(a, b, m):
    if not bool(m.any()): return float("nan")
    return 10 * math.log10(1 / max(float(((a - b)[:, m] ** 2).mean()), 1e-6))


variants = []
for s in specs:
    name, _, kv = s.partition(":")
    kw = {k: yaml.safe_load(x) for k, x in (a.split("=", 1) for a in kv.split(",") if a)}
    variants.append((name, PhotoSettings(**kw)))
rows = []
for n, p in enumerate([p for p in index.pairs if p.kind == "delete"]):
    rec = recs[(p.world, p.variation, p.frame)]
    image = load_frame(rec, size, semantic=False, instances=False).image
    scene = scene_from_frame(rec, size)
    target = torch.from_numpy(load_pair_rgb(root, p)).permute(2, 0, 1).float() / 255
    vac = torch.from_numpy(load_pair_mask(root, p, "vacated")); sh = torch.from_numpy(load_pair_mask(root, p, "shadow"))
    hole = vac | sh
    row = {"key": p.key, "variation": p.variation, "hole_px": int(hole.sum()), "m": {}, "sig": []}
    for name, st in variants:
        LOG.clear()
        t = time.process_time()
        ed = apply_edits(scene, [Delete(p.instance_id)])
        pic = T.render_photo(image, frame, scene, ed, settings=st, source=T.PhotoSource(image, frame, scene, settings=st, max_fills=0)).image.float().clamp(0, 1)
        row["m"][name] = {"psnr": psnr(pic, target, hole), "cpu": time.process_time() - t}
        if name == sig: row["sig"] = list(LOG)
    rows.append(row)
    print(n, p.key, {k: round(v["psnr"], 2) for k, v in row["m"].items()}, flush=True)
out_path.write_text(json.dumps({"root": str(root), "specs": specs, "rows": rows}))
