# ruff: noqa: E402, E501, E701, E702
"""fig.py TREE WORLD VAR FRAME ID BASE_CACHE NEW_CACHE OUT.png: one semantic proposal (instance ID) before and after:
photo, ground-truth mask (oracle), the semantic mask with the band the fit ignores, the fitted car's silhouette on main
and on this branch (each titled with its distance against the truth), enlarged 5x."""
import os
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.photo.transfer import _rasterize
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.meshes.bank import default_bank
from sdn3d.proposal_fit import unsure_below
from sdn3d.scene.maps import posed_meshes

tree, world, var, frame, iid, bc, nc, out = sys.argv[1:9]; iid = int(iid)
rec = index_records(read_frames(tree))[(world, var, int(frame))]
def load(cache):
    for line in open(os.path.join(cache, "keys.txt")):
        k, f = line.rsplit(" ", 1)
        if k.startswith(f"{world}_{var}_{int(frame)}_") and "semantic" in k.lower(): return torch.load(os.path.join(cache, f.strip()), weights_only=False)
base, new = load(bc), load(nc)
gt = scene_from_frame(rec, (312, 96))
def sil(scene):
    rows, verts, faces = posed_meshes(scene.objects, default_bank())
    r = _rasterize(rows, verts, faces, scene.intrinsics.matrix(dtype=torch.float64), (96, 312))
    mesh = r.frags.pix_to_mesh[0]
    return ((mesh >= 0) & (scene.objects.instance_id[r.rows[mesh.clamp(min=0)]] == iid)).numpy()
i = int((new.objects.instance_id == iid).nonzero()[0, 0])
pm = new.objects.mask[i].numpy()
band = unsure_below(new.objects.mask)[i].numpy()
inter = (gt.objects.mask & new.objects.mask[i]).flatten(1).sum(1); g = int(inter.argmax()); gm = gt.objects.mask[g].numpy()
zt = float(gt.objects.location[g, 2])
zb = float(base.objects.location[int((base.objects.instance_id == iid).nonzero()[0, 0]), 2]); zn = float(new.objects.location[i, 2])
sb, sn = sil(base), sil(new)
img = np.asarray(Image.open(rec.rgb_path).convert("RGB").resize((312, 96), Image.BILINEAR))
ys, xs = np.nonzero(gm | pm | sb | sn | band); x0, x1 = max(0, xs.min() - 8), min(312, xs.max() + 9); y0, y1 = max(0, ys.min() - 6), min(96, ys.max() + 7)
def tile(a, name, b=None):
    a = a[y0:y1, x0:x1]
    if a.ndim == 2:
        c = img[y0:y1, x0:x1] // 2
        c = np.where(a[..., None], np.array([255, 60, 60]), c)
        if b is not None: c = np.where(b[y0:y1, x0:x1, None], np.array([255, 220, 0]), c)
        a = c.astype(np.uint8)
    t = Image.fromarray(a).resize(((x1 - x0) * 5, (y1 - y0) * 5), Image.NEAREST)
    c = Image.new("RGB", (t.width, t.height + 14), "white"); c.paste(t, (0, 14)); ImageDraw.Draw(c).text((2, 1), name, fill="black"); return c
ts = [tile(img, f"seed tree {os.path.basename(tree)}: {world}/{var} {frame}"), tile(gm, f"ground-truth mask (oracle), {zt:.0f} m"), tile(pm, "semantic mask, band (yellow)", band),
      tile(sb, f"fitted car, main: {zb:.0f} m"), tile(sn, f"fitted car, this branch: {zn:.0f} m")]
W = sum(t.width for t in ts) + 16; c = Image.new("RGB", (W, ts[0].height), "white"); x = 0
for t in ts: c.paste(t, (x, 0)); x += t.width + 4
c.save(out); print(out, zt, zb, zn)
