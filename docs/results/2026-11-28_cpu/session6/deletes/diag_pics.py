# ruff: noqa: E402, E501, E701, E702, E401, I001
"""Delete diagnosis on counterfactual pairs (oracle: ground-truth geometry, scene_from_frame), session 5: the photo
path's rays against the 2D baseline's plain rays, and ablations between them. Runs whichever sdn3d is on PYTHONPATH.
usage: diag_deletes.py ROOT OUT.json VARIANT...   VARIANT = name[:key=val,...][+switch+switch...]
switches: 2d (baseline_photo '2d'), centre (the picture's centre as vanishing point), noamodal (apply_edits
amodal=False), nosil (the hole without the removed car's fitted silhouette), nodark (no shadowed road at all: none
joins the hole, none is kept out), srcall (the removed car's shadow joins the hole, every other shadowed pixel is a
source), srcbelowK (shadowed road kept out only from K/10 of the hole's height down: K=5 is what the code now does),
srcconn[K] (kept out only where connected to the hole), srcnearK (kept out only within K px of the hole);
with rejected_blind_vp.diff applied: blind0 (no blind-vanishing-point fallback), resttelea (Telea as the fallback).
(delete_shadow=false as a setting: the shadow not joined.) Per pair: PSNR on vacated | shadow, split into the
shadow-only pixels (sh), the vacated lower half (low) and upper half (up); the benchmark's darkening; CPU s.
"""
import json, math, sys, time
from pathlib import Path
import numpy as np, torch, yaml
from sdn3d.data.counterfactual import load_pair_mask, load_pair_rgb, load_pairs
from sdn3d.data.frames import load_frame
from sdn3d.data.records import load_instances, load_semantic
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import apply_edits
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.ops import Delete
from sdn3d.editing.photo.settings import PhotoSettings
import sdn3d.editing.photo.transfer as T
import sdn3d.editing.photo.road as R
from sdn3d.evaluation.counterfactual import darkening, road_ring
from sdn3d.evaluation.baselines import baseline_photo
from sdn3d.data.edit_benchmark import BenchmarkOperation
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.scene.maps import compose_instances
from sdn3d.editing.photo.fill import vacated_hole
torch.set_num_threads(1)
root, out_path, specs = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3:]
index = load_pairs(root); size = index.image_size
recs = {(r.world, r.variation, r.frame): r for r in read_frames(root, worlds=sorted({p.world for p in index.pairs}))}
ring_px = max(3, round(size[0] / 50)); frame = PixelFrame(size, size)
def psnr(a, b, m):
    if not bool(m.any()): return float("nan")
    return 10 * math.log10(1 / max(float(((a - b)[:, m] ** 2).mean()), 1e-6))
orig = {"vp": T.removal_vanishing_point, "rwe": T._remove_with_effects, "sr": R.shadowed_road, "rays": T._rays_with_effects}
STATE = {}
def patch(sw):
    T.removal_vanishing_point = (lambda image, K, removed, objects_px, ry=None: ((removed.shape[1]-1)/2, (removed.shape[0]-1)/2)) if "centre" in sw else orig["vp"]
    def rwe(image, hole, objects_px, before, gone_rows, K, light, settings, vanishing=None):
        if "nosil" in sw:
            hole = hole & STATE["base_hole"]
            objects_px = STATE["objects"] & ~hole
        return orig["rwe"](image, hole, objects_px, before, gone_rows, K, light, settings, vanishing)
    T._remove_with_effects = rwe
    R.shadowed_road = (lambda *a, **k: torch.zeros_like(a[2])) if "nodark" in sw else orig["sr"]
    if hasattr(R, "BLIND_VP"):  # only with rejected_blind_vp.diff applied (runs blind33 / blind31)
        R.BLIND_VP = "blind0" not in sw
        import sdn3d.editing.photo.fill as _fill
        _fill.RAY_REST = "telea" if "resttelea" in sw else "auto"
    mode = next((x for x in sw if x.startswith("src")), None)
    T._rays_with_effects = orig["rays"] if mode is None else (lambda *a, **k: rays_variant(mode, *a, **k))
from sdn3d.image_ops import dilate_square
from sdn3d.editing.photo.fill import fill_hole
import cv2
def rays_variant(mode, image, hole, objects_px, search, ring, road, settings, vanishing):
    ys, xs = (search | hole).nonzero(as_tuple=True)
    reach = max(int(ys.max() - ys.min()), int(xs.max() - xs.min())) + 8
    near = dilate_square(search | hole, reach)
    lit = near & ~dilate_square(search | hole, 3) & ~objects_px
    dark = orig["sr"](image, road, near, lit, settings.shadow_light) & ~objects_px
    own = dark & dilate_square(search, 3) & ~hole
    hole2 = hole | own
    matte = -own.float()
    if mode == "srcall":
        out_ = objects_px
    elif mode.startswith("srcconn"):
        # dark blobs touching the hole (the removed car's own shadow and what continues it) stay out; others are sources
        k = int(mode[7:] or 0)
        n, lab = cv2.connectedComponents(dark.numpy().astype(np.uint8), connectivity=8)
        lab = torch.from_numpy(lab)
        touch = lab[dilate_square(hole2, 1 + k) & dark].unique()
        touch = touch[touch > 0]
        out_ = objects_px | (torch.isin(lab, touch) & dark)
    elif mode.startswith("srcbelow"):
        # dark road is kept out only from the hole's rows share k/10 down: the ground the car's shadow lies on
        k = int(mode[8:])
        hy = hole2.nonzero()[:, 0]
        cut = int(hy.min()) + (int(hy.max()) - int(hy.min())) * k // 10
        below = torch.zeros_like(dark); below[cut:] = True
        out_ = objects_px | (dark & below)
    elif mode.startswith("srcnear"):
        k = int(mode[7:])
        out_ = objects_px | (dark & dilate_square(hole2, k))
    return fill_hole(image, hole2, settings, out_, vanishing=vanishing), matte
variants = []
for s in specs:
    head, *sw = s.split("+")
    name, _, kv = head.partition(":")
    kw = {k: yaml.safe_load(x) for k, x in (a.split("=", 1) for a in kv.split(",") if a)}
    variants.append((name, PhotoSettings(**kw), set(sw)))
rows = []
PICS = {}
import os
KEYS = os.environ.get('KEYS', '').split(',') if os.environ.get('KEYS') else None
for n, p in enumerate([p for p in index.pairs if p.kind == "delete"]):
    if KEYS and p.key.split()[0] not in KEYS: continue
    rec = recs[(p.world, p.variation, p.frame)]
    image = load_frame(rec, size, semantic=False, instances=False).image
    scene = scene_from_frame(rec, size)
    road = torch.from_numpy(load_semantic(rec)).long() == VKITTI_CLASS_INDEX["Road"]
    cars = torch.from_numpy(load_instances(rec)).long() != 0
    target = torch.from_numpy(load_pair_rgb(root, p)).permute(2, 0, 1).float() / 255
    vac = torch.from_numpy(load_pair_mask(root, p, "vacated")); sh = torch.from_numpy(load_pair_mask(root, p, "shadow"))
    hole = vac | sh; band = sh & road; ring = road_ring(sh, vac, road, cars, ring_px)
    inst = compose_instances(scene).cpu()
    gone = torch.tensor([p.instance_id]); keep = (inst != 0) & ~torch.isin(inst, gone)
    row = {"key": p.key, "hole_px": int(hole.sum()), "target_dark": darkening(target, band, ring), "m": {}}
    for name, st, sw in variants:
        STATE["base_hole"] = vacated_hole(inst, gone, keep, st); STATE["objects"] = inst != 0
        patch(sw)
        t = time.process_time()
        if "2d" in sw:
            from sdn3d.editing.apply import projected_centers
            uv, _ = projected_centers(scene); r_ = int((scene.objects.instance_id == p.instance_id).nonzero()[0, 0])
            pic = baseline_photo(image, scene, [BenchmarkOperation.delete(tuple(float(v) for v in uv[r_].tolist()))], "2d", None, st)
        else:
            ed = apply_edits(scene, [Delete(p.instance_id)], amodal="noamodal" not in sw)
            pic = T.render_photo(image, frame, scene, ed, settings=st, source=T.PhotoSource(image, frame, scene, settings=st, max_fills=0)).image.float()
        dt = time.process_time() - t
        pic = pic.clamp(0, 1)
        PICS.setdefault(p.key, {'input': image, 'target': target, 'hole': hole})[name] = pic
        lo = vac.clone(); ys = vac.nonzero()[:, 0]; lo[: int(ys.float().median()) if len(ys) else 0] = False
        row["m"][name] = {"psnr": psnr(pic, target, hole), "sh": psnr(pic, target, sh & ~vac), "low": psnr(pic, target, lo & ~sh),
                          "up": psnr(pic, target, vac & ~lo & ~sh), "dark": darkening(pic, band, ring), "cpu": dt,
                          "sse": float(((pic - target)[:, hole] ** 2).sum())}
    rows.append(row)
    print(n, p.key, {k: round(v["psnr"], 2) for k, v in row["m"].items()}, flush=True)
summ = {}
for name, _, _ in variants:
    summ[name] = {m: round(float(np.nanmean([r["m"][name][m] for r in rows])), 3) for m in ("psnr", "sh", "low", "up", "dark", "cpu")}
print(json.dumps(summ, indent=1))
out_path.write_text(json.dumps({"root": str(root), "specs": specs, "summary": summ, "rows": rows}))

torch.save(PICS, str(out_path) + '.pics.pt')
