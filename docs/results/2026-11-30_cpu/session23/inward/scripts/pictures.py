"""pictures.py OUT.png ROW TREE MAIN.json BRANCH.json FRAME:ID...: one row per car of two codes' pose tables
(benchmarks/pose_table.py --out, row ROW: gt_fit or pred_fit): the photo crop with the car's ground-truth mask
outline (an oracle), then main's fitted yaw, the branch's and the truth's, each drawn as the car's true mesh (its
template, size and place: the oracle's, so that only the yaw differs) turned to that yaw, outlined, with an arrow
from the centre to the front. Every panel titled (what, which code, its yaw error)."""
import json
import math
import os
import sys

import numpy as np
import torch
from PIL import Image, ImageDraw

from sdn3d.data.scene_gt import frame_photo, scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.evaluation.edit_benchmark import index_records
from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes.bank import default_bank
from sdn3d.render import RasterSettings, rasterize_meshes
from sdn3d.render.objects import pose_meshes

ROWS = {"gt_fit": "fit, oracle: ground-truth masks + boxes", "pred_fit": "fit, predicted proposals"}
S = 4  # display scale of the 312x96 working size's pixels


def wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def outline(mask: torch.Tensor) -> np.ndarray:
    m = mask.numpy()
    return m & ~(np.roll(m, 1, 0) & np.roll(m, -1, 0) & np.roll(m, 1, 1) & np.roll(m, -1, 1))


def draw_pose(K, tpl, dims, ry, center, phi):
    verts, faces = pose_meshes(default_bank(), tpl[None], dims[None].float(), ry[None].float(),
                               center[None].float(), phi[None].float())
    mask = rasterize_meshes(verts, faces, K, RasterSettings((96, 312))).mask[0]
    pts = object_to_camera(torch.tensor([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]), dims[None].float(), ry[None].float(),
                           center[None].float())[0]
    uv = (K @ pts.T).T
    return mask, uv[:, :2] / uv[:, 2:3], bool(pts[1, 2] < pts[0, 2])


out, row, tree, main_json, branch_json = sys.argv[1:6]
records = index_records(read_frames(tree))
yaws = {name: {(o["frame"], o["id"]): o["ry"] for o in json.load(open(f))["objects"][ROWS[row]]}
        for name, f in (("main", main_json), ("branch", branch_json))}
torch.set_num_threads(1)
rows = []
for it in sys.argv[6:]:
    src, iid = it.rsplit(":", 1)
    _, w, var, fr = src.split("/")
    rec = records[(w, var, int(fr))]
    scene = scene_from_frame(rec, (312, 96))
    truth, K = scene.objects, scene.intrinsics.matrix().float()
    t = int((truth.instance_id == int(iid)).nonzero()[0])
    photo = frame_photo(rec, (312, 96)).image
    img = torch.nn.functional.interpolate(photo[None], size=(96 * S, 312 * S), mode="bilinear",
                                          align_corners=False)[0]
    img = (img.clamp(0, 1).permute(1, 2, 0).numpy() * 255).astype(np.uint8)
    poses = {}
    for name in ("main", "branch", "truth"):
        ry = truth.ry[t] if name == "truth" else torch.tensor(yaws[name][(src, int(iid))])
        poses[name] = (*draw_pose(K, truth.template_id[t], truth.dims[t].float(), ry, truth.center[t].float(),
                                  truth.phi[t]), float(ry))
    m0 = truth.mask[t]
    ys, xs = m0.nonzero(as_tuple=True)
    y0, y1 = max(0, int(ys.min()) - 6), min(96, int(ys.max()) + 7)
    x0, x1 = max(0, int(xs.min()) - 10), min(312, int(xs.max()) + 11)
    panels = []
    for title, key, colour in (("photo + true mask (oracle)", None, (200, 200, 200)),
                               ("main's fit", "main", (255, 60, 60)), ("branch's fit", "branch", (60, 255, 60)),
                               ("ground truth (oracle)", "truth", (80, 160, 255))):
        a = img.copy()
        m = m0 if key is None else poses[key][0]
        a[np.kron(outline(m), np.ones((S, S), dtype=bool))] = colour
        p = Image.fromarray(a[y0 * S:y1 * S, x0 * S:x1 * S])
        d = ImageDraw.Draw(p)
        if key is not None:
            (u0, v0), (u1, v1) = (poses[key][1] * S - torch.tensor([x0 * S, y0 * S])).tolist()
            d.line([(u0, v0), (u1, v1)], fill=colour, width=3)
            d.ellipse([u1 - 5, v1 - 5, u1 + 5, v1 + 5], fill=colour)
            err = abs(math.degrees(wrap(poses[key][3] - poses["truth"][3])))
            title = (f"{title}: {'' if key == 'truth' else f'{err:.0f} deg off, '}"
                     + ("front to camera" if poses[key][2] else "back to camera"))
        tile = Image.new("RGB", (max(p.width, 260), p.height + 16), "white")
        tile.paste(p, (0, 16))
        ImageDraw.Draw(tile).text((2, 2), title, fill="black")
        panels.append(tile)
    strip = Image.new("RGB", (sum(p.width for p in panels) + 6 * len(panels), max(p.height for p in panels) + 16),
                      "white")
    ImageDraw.Draw(strip).text((2, 2), f"{src} id {iid}, {ROWS[row]} (mesh: the true one at the fitted yaw; arrow: "
                                       f"centre to front)", fill="black")
    x = 0
    for p in panels:
        strip.paste(p, (x, 16))
        x += p.width + 6
    rows.append(strip)
sheet = Image.new("RGB", (max(r.width for r in rows), sum(r.height + 8 for r in rows)), "white")
y = 0
for r in rows:
    sheet.paste(r, (0, y))
    y += r.height + 8
tmp = out + ".tmp.png"
sheet.save(tmp)
os.replace(tmp, out)
