"""Delete-only tuning/diagnosis harness on counterfactual pairs (ground-truth geometry: oracle).

usage: cf_deletes.py ROOT OUT.json VARIANT [VARIANT ...] [--png DIR] [--limit N] [--only i,j,...]
VARIANT: name or name:key=val,key=val (PhotoSettings keys; 'base' = defaults), or name:avg=a+b (two variants'
mean picture). Runs with whichever sdn3d is on PYTHONPATH (main's code: its worktree's src).
Per pair: PSNR on hole (vacated | shadow), split into road / non-road (GT semantic of the source frame) and the
shadow band; the benchmark's darkening (sdn3d.evaluation.counterfactual.darkening on band & road vs road ring);
the photo path's draw time.
"""

import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import torch
import yaml
from PIL import Image

from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.records import load_instances, load_semantic
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.transfer import PhotoSource, render_photo
from sdn3d.evaluation.counterfactual import darkening, road_ring
from sdn3d.labels import VKITTI_CLASS_INDEX

torch.set_num_threads(1)

# Experiments of the records (environment switches, harness only):
# CENTRE=1: the picture's centre as the rays' vanishing point; NOLIGHT=1: no fitted light at all;
# HZ_PATCH=1: rays below the horizon row only (Telea above); AMODAL=0: apply_edits without amodal completion.
if os.environ.get("CENTRE"):
    import sdn3d.editing.photo.transfer as _t

    _t.removal_vanishing_point = lambda image, K, removed, objects_px, ry=None: (
        (removed.shape[1] - 1) / 2,
        (removed.shape[0] - 1) / 2,
    )
if os.environ.get("NOLIGHT"):
    import sdn3d.editing.photo.transfer as _t

    _t.PhotoSource.light = lambda self: (None, None)
if os.environ.get("HZ_PATCH"):
    import sdn3d.editing.photo.road as _road

    _ray_fill = _road.ray_fill

    def _below_horizon(image, hole, vp, keep_out=None, *a, **k):
        out, reached = _ray_fill(image, hole, vp, keep_out, *a, **k)
        reached[: max(int(vp[1]), 0)] = False
        return out, reached

    _road.ray_fill = _below_horizon
args = sys.argv[1:]
png_dir = None
limit = None
if "--png" in args:
    i = args.index("--png")
    png_dir = Path(args[i + 1])
    del args[i : i + 2]
    png_dir.mkdir(parents=True, exist_ok=True)
only = None
if "--only" in args:  # comma-separated indices of the delete pairs
    i = args.index("--only")
    only = [int(x) for x in args[i + 1].split(",")]
    del args[i : i + 2]
if "--limit" in args:
    i = args.index("--limit")
    limit = int(args[i + 1])
    del args[i : i + 2]
root, out_path, variants = Path(args[0]), Path(args[1]), args[2:]
parsed = {}
mixes = {}
for v in variants:
    name, _, kv = v.partition(":")
    if kv.startswith("avg="):  # name:avg=a+b (the mean of two variants' pictures)
        mixes[name] = kv[4:].split("+")
        continue
    kw = {k: yaml.safe_load(x) for k, x in (a.split("=", 1) for a in kv.split(",") if a)}
    parsed[name] = PhotoSettings(**kw)
index = load_pairs(root)
size = index.image_size
recs = {(r.world, r.variation, r.frame): r for r in read_frames(root, worlds=sorted({p.world for p in index.pairs}))}
ring_px = max(3, round(size[0] / 50))
frame = PixelFrame(size, size)


def lap(x, m):
    """mean absolute 3x3 Laplacian of the luma of ``x (3, H, W)`` over ``m``"""
    import cv2

    y = (x.permute(1, 2, 0).numpy() @ np.array([0.2126, 0.7152, 0.0722], np.float32)).astype(np.float32)
    return float(np.abs(cv2.Laplacian(y, cv2.CV_32F, ksize=1))[m.numpy()].mean()) if bool(m.any()) else float("nan")


def psnr(a, b, m):
    if not bool(m.any()):
        return float("nan")
    e = float(((a - b)[:, m] ** 2).mean())
    return 10 * math.log10(1 / max(e, 1e-6))


rows = []
pairs = [p for p in index.pairs if p.kind == "delete"][:limit]
if only is not None:
    pairs = [pairs[i] for i in only]
for n, p in enumerate(pairs):
    rec = recs[(p.world, p.variation, p.frame)]
    fr = load_frame(rec, size, semantic=False, instances=False)
    image = fr.image
    scene = scene_from_frame(rec, size)
    road = torch.from_numpy(load_semantic(rec)).long() == VKITTI_CLASS_INDEX["Road"]
    cars = torch.from_numpy(load_instances(rec)).long() != 0
    target = torch.from_numpy(load_pair_rgb(root, p)).permute(2, 0, 1).float() / 255
    vac = torch.from_numpy(load_pair_mask(root, p, "vacated"))
    sh = torch.from_numpy(load_pair_mask(root, p, "shadow"))
    hole = vac | sh
    band = sh & road
    ring = road_ring(sh, vac, road, cars, ring_px)
    # road under the car in the target: target semantic not stored; use: source road | (vacated and below horizon)
    row = {
        "key": p.key,
        "hole_px": int(hole.sum()),
        "vac_px": int(vac.sum()),
        "sh_px": int(sh.sum()),
        "target_dark": darkening(target, band, ring),
        "input_dark": darkening(image, band, ring),
        "input_psnr": psnr(image, target, hole),
        "m": {},
    }
    ed = apply_edits(scene, [Delete(p.instance_id)], amodal=os.environ.get("AMODAL", "1") != "0")
    iid = p.instance_id
    pics = {}
    for name in list(parsed) + list(mixes):
        if name in mixes:
            a, b = mixes[name]
            pic, dt = (pics[a][0] + pics[b][0]) / 2, (row["m"][a]["ms"] + row["m"][b]["ms"]) / 1000
        else:
            st = parsed[name]
            src = PhotoSource(image, frame, scene, settings=st, max_fills=0)
            t = time.perf_counter()
            r = render_photo(image, frame, scene, ed, settings=st, source=src)
            dt = time.perf_counter() - t
            pic = r.image.float().clamp(0, 1)
        pics[name] = (pic, None)
        # split: pixels of the hole that are target-road-ish: use the target's similarity? Use regions:
        # band (shadow mask & ~vacated), vacated lower half (road under car: rows below the car's centre), upper
        vs = vac & ~sh
        ys = vac.nonzero()[:, 0]
        mid = float(ys.float().median()) if len(ys) else 0
        low = vac.clone()
        low[: int(mid)] = False
        up = vac & ~low
        row["m"][name] = {
            "psnr": psnr(pic, target, hole),
            "psnr_shadow": psnr(pic, target, sh & ~vac),
            "psnr_vac_low": psnr(pic, target, low),
            "psnr_vac_up": psnr(pic, target, up),
            "psnr_roadsrc": psnr(pic, target, hole & road),
            "dark": darkening(pic, band, ring),
            "ms": 1000 * dt,
            "lap_ratio": lap(pic, hole & road) / max(lap(target, hole & road), 1e-6),
            "mse": float(((pic - target)[:, hole] ** 2).mean()),
            "mse_sh": float(((pic - target)[:, sh & ~vac] ** 2).sum()) / max(int(hole.sum()), 1),
            "mse_low": float(((pic - target)[:, low & ~sh] ** 2).sum()) / max(int(hole.sum()), 1),
            "mse_up": float(((pic - target)[:, up & ~sh] ** 2).sum()) / max(int(hole.sum()), 1),
        }
    rows.append(row)
    print(n, p.key, {k: round(v["psnr"], 2) for k, v in row["m"].items()}, flush=True)
    if png_dir is not None:
        ys, xs = (hole | cars & (torch.from_numpy(load_instances(rec)).long() == iid)).nonzero(as_tuple=True)
        y0, y1 = max(int(ys.min()) - 20, 0), min(int(ys.max()) + 20, size[1])
        x0, x1 = max(int(xs.min()) - 40, 0), min(int(xs.max()) + 40, size[0])
        tiles = [image, target] + [pics[k][0] for k in pics]
        strip = torch.cat([t[:, y0:y1, x0:x1] for t in tiles], 2)
        outline = torch.zeros_like(strip[0], dtype=torch.bool)
        Image.fromarray((strip.permute(1, 2, 0).numpy() * 255).astype(np.uint8)).save(
            png_dir / f"{n:02d}_{p.world}_{p.variation}_{p.frame}_{iid}.png"
        )
names = list(parsed) + list(mixes)
summ = {}
for k in names:
    s = {}
    for m in (
        "lap_ratio",
        "psnr",
        "psnr_shadow",
        "psnr_vac_low",
        "psnr_vac_up",
        "dark",
        "ms",
        "mse_sh",
        "mse_low",
        "mse_up",
    ):
        vals = [r["m"][k][m] for r in rows if math.isfinite(r["m"][k][m])]
        s[m] = round(float(np.mean(vals)), 4) if vals else None
    s["ms_max"] = round(max(r["m"][k]["ms"] for r in rows), 1)
    summ[k] = s
summ["_target_dark"] = float(np.nanmean([r["target_dark"] for r in rows]))
summ["_input_dark"] = float(np.nanmean([r["input_dark"] for r in rows]))
summ["_input_psnr"] = float(np.nanmean([r["input_psnr"] for r in rows]))
print(json.dumps(summ, indent=1))
out_path.parent.mkdir(parents=True, exist_ok=True)
out_path.write_text(json.dumps({"root": str(root), "variants": variants, "summary": summ, "rows": rows}))
