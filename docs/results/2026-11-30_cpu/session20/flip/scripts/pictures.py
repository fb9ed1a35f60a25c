# ruff: noqa: E501, E701, E702
"""pictures.py TREE CAP_MAIN CAP_BRANCH OUT.png SRC:ID [...]: one row per car of a captured Table 1 source scene
(capture.py of main's code and of the branch's: the same masks, each code's lamp readings), fitted by each code
(proposal_fit.fit_proposals, default settings): the photo crop with the proposal's mask outline (grey), then main's fit,
the branch's and the ground truth's (an oracle) pose each drawn as its mesh's outline over the crop, with an arrow from
the car's centre to its front (the end the fit chose). Panels titled; the row's label: frame, id, yaw errors."""
import math
import os
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

import sdn3d.proposal_fit as pf
from sdn3d.data.scene_gt import frame_photo, scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.geometric.fit import FitSettings
from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import default_bank
from sdn3d.render import RasterSettings, rasterize_meshes
from sdn3d.render.objects import pose_meshes

tree, cap_main, cap_branch, out = sys.argv[1:5]
items = sys.argv[5:]
records = index_records(read_frames(tree))
torch.set_num_threads(1)
S = 4  # display scale of the 312x96 working size's pixels


def wrap(a): return (a + math.pi) % (2 * math.pi) - math.pi


def outline(mask):
    m = mask.numpy()
    edge = m & ~(np.roll(m, 1, 0) & np.roll(m, -1, 0) & np.roll(m, 1, 1) & np.roll(m, -1, 1))
    return edge


def draw_pose(K, tpl, dims, ry, center, phi):
    verts, faces = pose_meshes(default_bank(), tpl[None], dims[None].float(), ry[None].float(), center[None].float(), phi[None].float())
    mask = rasterize_meshes(verts, faces, K, RasterSettings((96, 312))).mask[0]
    pts = object_to_camera(torch.tensor([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]), dims[None].float(), ry[None].float(), center[None].float())[0]
    uv = (K @ pts.T).T; uv = uv[:, :2] / uv[:, 2:3]
    return mask, uv, bool(pts[1, 2] < pts[0, 2])


rows = []
for it in items:
    src, iid = it.rsplit(":", 1); _, w, var, fr = src.split("/")
    rec = records[(w, var, int(fr))]
    truth = scene_from_frame(rec, (312, 96)).objects
    photo = frame_photo(rec, (312, 96)).image
    img = torch.nn.functional.interpolate(photo[None], size=(96 * S, 312 * S), mode="bilinear", align_corners=False)[0]
    img = (img.clamp(0, 1).permute(1, 2, 0).numpy() * 255).astype(np.uint8)
    poses = {}
    for name, cap in (("main", cap_main), ("branch", cap_branch)):
        c = torch.load(f"{cap}/{w}_{var}_{fr}.pt", weights_only=False)
        r = int((c["ids"] == int(iid)).nonzero()[0])
        g, _ = pf.fit_proposals(c["intr"], c["masks"], c["ids"], c["rows"], c["geometry"], FitSettings(), c["appearance"], c["unsure"], c["classes"])
        tpl, dims, ry, loc, phi = (x[r] for x in g)
        center = loc.clone().float(); center[1] -= float(dims[1]) / 2
        K = c["intr"].matrix()
        poses[name] = (*draw_pose(K, tpl, dims.float(), ry, center, phi), float(ry))  # mask, uv, front nearer, ry
        prop = c["masks"][r]
    iou = (prop[None] & truth.mask).flatten(1).sum(1).float() / (prop[None] | truth.mask).flatten(1).sum(1).float().clamp_min(1)
    t = int(iou.argmax())
    poses["truth"] = (*draw_pose(K, truth.template_id[t], truth.dims[t].float(), truth.ry[t], truth.center[t].float(), truth.phi[t]), float(truth.ry[t]))
    ys, xs = prop.nonzero(as_tuple=True)
    y0, y1 = max(0, int(ys.min()) - 6), min(96, int(ys.max()) + 7); x0, x1 = max(0, int(xs.min()) - 10), min(312, int(xs.max()) + 11)
    panels = []
    for title, key, colour in (("photo + proposal mask", None, (200, 200, 200)), ("main's fit", "main", (255, 60, 60)),
                               ("branch's fit", "branch", (60, 255, 60)), ("ground truth (oracle)", "truth", (80, 160, 255))):
        a = img.copy()
        m = prop if key is None else poses[key][0]
        e = np.kron(outline(m), np.ones((S, S), dtype=bool))
        a[e] = colour
        p = Image.fromarray(a[y0 * S:y1 * S, x0 * S:x1 * S])
        d = ImageDraw.Draw(p)
        if key is not None:
            uv = poses[key][1] * S - torch.tensor([x0 * S, y0 * S])
            (u0, v0), (u1, v1) = uv.tolist()
            d.line([(u0, v0), (u1, v1)], fill=colour, width=3); d.ellipse([u1 - 5, v1 - 5, u1 + 5, v1 + 5], fill=colour)
            err = abs(math.degrees(wrap(poses[key][3] - poses["truth"][3])))
            title = (f"{title}: ry {math.degrees(poses[key][3]):.0f}" + ("" if key == "truth" else f", {err:.0f} off")
                     + (", front to camera" if poses[key][2] else ", back to camera"))
        tile = Image.new("RGB", (max(p.width, 300), p.height + 16), "white"); tile.paste(p, (0, 16))
        ImageDraw.Draw(tile).text((2, 2), title, fill="black")
        panels.append(tile)
    row = Image.new("RGB", (sum(t.width for t in panels) + 6 * len(panels), max(t.height for t in panels) + 16), "white")
    ImageDraw.Draw(row).text((2, 2), f"{src} id {iid} (arrow: centre to the fitted front)", fill="black")
    x = 0
    for t in panels: row.paste(t, (x, 16)); x += t.width + 6
    rows.append(row)
sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 8 for r in rows)), "white")
y = 0
for r in rows: sheet.paste(r, (0, y)); y += r.height + 8
tmp = out + ".tmp.png"; sheet.save(tmp)
os.replace(tmp, out)
