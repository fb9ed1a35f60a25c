# ruff: noqa: E402, E501, E701, E702
"""maskview.py TREE CACHE WORLD VAR FRAME SOURCE(gt|semantic) U V OUT.png: the source frame around the object at
working pixel (U, V): picture, ground-truth mask (oracle), the de-rendered scene's mask of the picked object, and
its fitted silhouette (the scene's posed mesh), each panel titled, enlarged 5x."""
import os
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import match_objects
from sdn3d.editing.photo.transfer import _rasterize
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.meshes.bank import default_bank
from sdn3d.scene.maps import posed_meshes

tree, cache, world, var, frame, src = sys.argv[1:7]; u, v = float(sys.argv[7]), float(sys.argv[8]); out = sys.argv[9]
rec = index_records(read_frames(tree))[(world, var, int(frame))]
keys = {}
for line in open(os.path.join(cache, "keys.txt")):
    k, f = line.rsplit(" ", 1); keys[k.split("_FitSettings")[0]] = f.strip()
key = [k for k in keys if k.startswith(f"{world}_{var}_{int(frame)}_") and src in k.lower()][0]
scene = torch.load(os.path.join(cache, keys[key]), weights_only=False)
oracle = scene_from_frame(rec, (312, 96))
gi = match_objects(oracle, [(u, v)], [True])[0]; pi = match_objects(scene, [(u, v)], [True])[0]
gm = oracle.objects.mask[(oracle.objects.instance_id == gi).nonzero()[0, 0]].numpy()
pm = scene.objects.mask[(scene.objects.instance_id == pi).nonzero()[0, 0]].numpy()
rows, verts, faces = posed_meshes(scene.objects, default_bank())
K = scene.intrinsics.matrix(dtype=torch.float64)
r = _rasterize(rows, verts, faces, K, (96, 312))
mesh = r.frags.pix_to_mesh[0]
sil = ((mesh >= 0) & (scene.objects.instance_id[r.rows[mesh.clamp(min=0)]] == pi)).numpy() if len(r.rows) else np.zeros_like(pm)
img = np.asarray(Image.open(rec.rgb_path).convert("RGB").resize((312, 96), Image.BILINEAR))
ys, xs = np.nonzero(gm | pm | sil); x0, x1 = max(0, xs.min() - 8), min(312, xs.max() + 9); y0, y1 = max(0, ys.min() - 6), min(96, ys.max() + 7)
def tile(a, name):
    a = a[y0:y1, x0:x1]
    if a.ndim == 2: a = np.where(a[..., None], np.array([255, 60, 60]), img[y0:y1, x0:x1] // 2).astype(np.uint8)
    t = Image.fromarray(a).resize(((x1 - x0) * 5, (y1 - y0) * 5), Image.NEAREST)
    c = Image.new("RGB", (t.width, t.height + 14), "white"); c.paste(t, (0, 14)); ImageDraw.Draw(c).text((2, 1), name, fill="black"); return c
ts = [tile(img, f"{world}/{var} {frame}"), tile(gm, "ground-truth mask (oracle)"), tile(pm, f"{src} mask"), tile(sil, "fitted mesh (seen part)")]
W = sum(t.width for t in ts) + 12; c = Image.new("RGB", (W, ts[0].height), "white"); x = 0
for t in ts: c.paste(t, (x, 0)); x += t.width + 4
c.save(out)
o = scene.objects; r = int((o.instance_id == pi).nonzero()[0, 0]); g = int((oracle.objects.instance_id == gi).nonzero()[0, 0])
print("fit", o.location[r].tolist(), float(o.ry[r]), o.dims[r].tolist(), "truth", oracle.objects.location[g].tolist(), float(oracle.objects.ry[g]), oracle.objects.dims[g].tolist())
print([f for f in scene.meta.get("fits", []) if f["id"] == pi])
