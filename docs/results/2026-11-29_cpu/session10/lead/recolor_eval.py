# ruff: noqa
"""recolor_eval.py TREE OUT.json [MAXFRAMES]: every car (>= 400 visible pixels) of the frames recoloured (photo
appearance, the code on PYTHONPATH, ground-truth geometry = an oracle: scene_from_frame) to a colour far from its
paint; on the car's ground-truth visible pixels (instance map): the share of its paint (the largest colour cluster of
those pixels, recolor._paint, independent of the template) left unpainted, and the share of its other pixels
(windows, tyres, lamps, trim) repainted."""
import sys, json, numpy as np, torch
from sdn3d.cli._config import synth_data_source
from sdn3d.data.sources import load_split
from sdn3d.data.records import load_rgb, load_instances
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.editing.frame import PixelFrame
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.editing.photo.settings import PhotoSettings
from sdn3d.editing.photo.recolor import _paint, srgb_to_lab
root, out = sys.argv[1], sys.argv[2]; maxf = int(sys.argv[3]) if len(sys.argv) > 3 else 30
src = synth_data_source(root, (624, 192))
recs = [r for s in ("test", "val", "train") for r in load_split(src, s) if r.objects][:maxf]
rows = []
for rec in recs:
    rgb = load_rgb(rec); inst = load_instances(rec)
    H, W = inst.shape
    scene = scene_from_frame(rec, (W, H))
    original = torch.from_numpy(np.ascontiguousarray(rgb)).permute(2, 0, 1)
    img = original.float() / 255
    ids = [int(i) for i in scene.objects.instance_id.tolist() if (inst == i).sum() >= 400]
    for iid in ids:
        car = torch.from_numpy(inst == iid)
        cols = img.permute(1, 2, 0)[car].double()
        lab = srgb_to_lab(cols)
        paint = _paint(lab)
        ab = lab[paint, 1:].mean(0)
        coloured = float(ab.norm()) > 10
        # a target far from the paint: red for blue/green/grey paints, blue for red/orange/yellow ones
        target = (0.1, 0.25, 0.8) if coloured and float(ab[0]) > 10 else (0.8, 0.1, 0.1)
        res = render_photo(original, PixelFrame((W, H), (W, H)), scene, scene, settings=PhotoSettings(), recolor={iid: target})
        new = res.image.permute(1, 2, 0)[car].float() / 255
        changed = (new - cols.float()).abs().amax(1) > 2.5 / 255
        rows.append({"frame": rec.key, "id": iid, "coloured": coloured, "pixels": int(car.sum()), "paint": int(paint.sum()),
                     "paint_unpainted": float((~changed[paint]).double().mean()),
                     "other_repainted": float(changed[~paint].double().mean()) if bool((~paint).any()) else 0.0})
json.dump(rows, open(out, "w"))
for kind in (True, False):
    r = [x for x in rows if x["coloured"] == kind]
    if r:
        print(f"{'coloured' if kind else 'grey'} paints: n={len(r)} paint left unpainted mean {100*np.mean([x['paint_unpainted'] for x in r]):.1f} %, median {100*np.median([x['paint_unpainted'] for x in r]):.1f} %; other pixels repainted mean {100*np.mean([x['other_repainted'] for x in r]):.1f} %")
