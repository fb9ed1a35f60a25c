# ruff: noqa: E501, E701, E702, B905
"""real_maps.py [OUT.png] (run from the repository root): the real frame of tests/data through the demo's semantic
branch as Models.from_checkpoints loads it (the frame at the 624x192 working size, the branch at its 312x96 training
size), and its maps at 312x96: the centre heatmap's local maxima (above and under the threshold), the 8-connected
components of the thing pixels (thing_label with the defaults), each component's heatmap maximum, its pixels' votes
(pixel + offset: mean, spread, distance from the component's own centre of mass) and the grouping's instances.
Prints a table; OUT.png: photo | heatmap with local maxima | thing components | votes (each pixel's vote drawn in its
component's colour) | the grouping's instances (the installed sdn3d's defaults), each panel titled."""
import sys

import numpy as np
import torch
import torch.nn.functional as F
from PIL import Image, ImageDraw
from scipy import ndimage

from sdn3d.models import Models
from sdn3d.semantic.panoptic import group_vehicles, thing_label
from sdn3d.semantic.predict import network_size

torch.set_num_threads(1)
sem = Models.from_checkpoints(semantic="/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt").semantic
g = sem.grouping
rgb = np.asarray(Image.open("tests/data/0006_30-deg-right_00043.png").convert("RGB"))
img = torch.from_numpy(rgb.copy()).permute(2, 0, 1).float()[None] / 255
img = F.interpolate(img, size=(192, 624), mode="bilinear", antialias=True, align_corners=False)
w, h = network_size((624, 192), sem.trained_size)
work = F.interpolate(img, size=(h, w), mode="bilinear", antialias=True, align_corners=False)
with torch.no_grad():
    out = sem.net(work)
prob = out["logits"].softmax(1); center = out["center"]; offset = out["offset"]
things = sem.thing_classes
lab = thing_label(prob, things, g["thing_odds"])[0].numpy()
thing = np.isin(lab, things)
heat = center[0, 0].numpy()
pooled = F.max_pool2d(center, g["nms_kernel"], 1, g["nms_kernel"] // 2)[0, 0].numpy()
peaks = np.argwhere((heat == pooled) & (heat > 0.01))
order = np.argsort(-heat[peaks[:, 0], peaks[:, 1]])
print(f"branch at {w}x{h}; threshold {g['center_threshold']}; heatmap max {heat.max():.3f}")
print("local maxima of the heatmap above 0.01 (v, u, value):")
for v, u in peaks[order][:12]: print(f"  ({v:3d}, {u:3d}) {heat[v, u]:.3f}{'  <- centre' if heat[v, u] > g['center_threshold'] else ''}")
comp, n = ndimage.label(thing, structure=np.ones((3, 3)))
vv, uu = np.mgrid[0:h, 0:w]
vote_u = uu + offset[0, 0].numpy(); vote_v = vv + offset[0, 1].numpy()
print(f"thing pixels {int(thing.sum())}, 8-connected components {n}")
print(" comp  area  centroid(u,v)   bbox(u0-u1,v0-v1)   heat max (at)       mean vote (u,v)  vote sd  |mean vote - centroid|  votes within 3 px of own centroid")
sizes = np.bincount(comp.ravel())[1:]
for c in np.argsort(-sizes) + 1:
    m = comp == c; a = int(m.sum())
    cu, cv = uu[m].mean(), vv[m].mean()
    hm = np.where(m, heat, -1); hv, hu = np.unravel_index(hm.argmax(), hm.shape)
    mu, mv = vote_u[m].mean(), vote_v[m].mean()
    sd = np.sqrt(((vote_u[m] - mu) ** 2 + (vote_v[m] - mv) ** 2).mean())
    near = np.mean(np.hypot(vote_u[m] - cu, vote_v[m] - cv) < 3)
    print(f" {c:4d} {a:5d}  ({cu:6.1f},{cv:5.1f})  {uu[m].min():3d}-{uu[m].max():3d},{vv[m].min():2d}-{vv[m].max():2d}   {heat[hv, hu]:.3f} ({hu:3d},{hv:2d})   ({mu:6.1f},{mv:5.1f})  {sd:6.1f}   {np.hypot(mu - cu, mv - cv):6.1f}   {near:.2f}")
# gaps between the two largest components (Chebyshev distance of the nearest pixel pair)
big = np.argsort(-sizes)[:2] + 1
if len(big) == 2:
    dist = ndimage.distance_transform_cdt(comp != big[0], metric="chessboard")
    print(f"gap between the two largest components: {int(dist[comp == big[1]].min()) - 1} px (chessboard)")
inst, _ = group_vehicles(prob.argmax(1), prob, center, offset, things, thing_odds=g["thing_odds"], threshold=g["center_threshold"],
                         nms_kernel=g["nms_kernel"], top_k=g["top_k"], min_area=g["min_area"], split_separation=g["split_separation"],
                         **({"part_separation": g["part_separation"]} if "part_separation" in g else {}))
ids = [int(i) for i in inst.unique() if i > 0]
print("grouping's instances:", {i: int((inst == i).sum()) for i in ids})
if len(sys.argv) > 1:
    S = 3; pal = np.array([[230, 25, 75], [60, 180, 75], [0, 130, 200], [245, 130, 48], [145, 30, 180], [70, 240, 240], [240, 50, 230], [210, 245, 60], [250, 190, 212], [0, 128, 128]])
    photo = (work[0].permute(1, 2, 0).numpy() * 255).astype(np.uint8)
    def up(a): return np.asarray(Image.fromarray(a).resize((w * S, h * S), Image.NEAREST))
    p1 = up(photo)
    hm = (np.clip(heat / max(heat.max(), 1e-6), 0, 1) * 255).astype(np.uint8); p2 = up(np.stack([hm, hm, hm], -1))
    comp_rgb = (photo * 0.35).astype(np.uint8)
    for i, c in enumerate(np.argsort(-sizes) + 1): comp_rgb[comp == c] = pal[i % len(pal)]
    p3 = up(comp_rgb)
    p4 = up((photo * 0.35).astype(np.uint8))
    inst_rgb = (photo * 0.35).astype(np.uint8)
    for i, k in enumerate(ids): inst_rgb[inst[0].numpy() == k] = pal[i % len(pal)]
    p5 = up(inst_rgb)
    panels = [Image.fromarray(p) for p in (p1, p2, p3, p4, p5)]
    d2 = ImageDraw.Draw(panels[1])
    for v, u in peaks[order][:12]:
        col = (255, 0, 0) if heat[v, u] > g["center_threshold"] else (255, 200, 0)
        d2.ellipse([u * S - 5, v * S - 5, u * S + 5, v * S + 5], outline=col, width=2); d2.text((u * S + 6, v * S - 6), f"{heat[v, u]:.2f}", fill=col)
    d4 = ImageDraw.Draw(panels[3])
    for i, c in enumerate(np.argsort(-sizes)[:6] + 1):
        m = comp == c; col = tuple(int(x) for x in pal[i % len(pal)])
        for x, y in zip(vote_u[m][::2], vote_v[m][::2]): d4.point((x * S, y * S), fill=col)
        cu, cv = uu[m].mean(), vv[m].mean(); d4.rectangle([cu * S - 4, cv * S - 4, cu * S + 4, cv * S + 4], outline=(255, 255, 255), width=2)
    titles = [f"photo at the branch's {w}x{h}", f"centre heatmap (white = max {heat.max():.2f}); red: centres > {g['center_threshold']}, yellow: local maxima below",
              f"thing pixels (thing_odds {g['thing_odds']}): {n} 8-connected components, one colour each",
              "votes (pixel + offset) of the 6 largest components, in their colour; white squares: each component's centre of mass",
              f"the grouping ({'part_separation ' + str(g['part_separation']) if 'part_separation' in g else 'no part_separation'}): {len(ids)} instance(s), one colour each"]
    tw = w * S; th = 18
    sheet = Image.new("RGB", (tw, len(panels) * (h * S + th)), "white"); d = ImageDraw.Draw(sheet)
    for i, (p, t) in enumerate(zip(panels, titles)):
        y = i * (h * S + th); d.text((4, y + 3), t, fill="black"); sheet.paste(p, (0, y + th))
    sheet.save(sys.argv[1]); print("wrote", sys.argv[1])
