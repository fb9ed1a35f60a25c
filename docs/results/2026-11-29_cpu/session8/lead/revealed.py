# ruff: noqa: E402, E501, E701, E702
"""Which counterfactual delete pairs reveal another car behind the deleted one, and how each fill scores on pairs
with and without one (issue 41, the deletes' goal). A pair reveals a car when the projected 3D box (convex hull of its
8 corners) of another car of the source frame's motgt, farther than the deleted car, covers at least 10 % of the
vacated mask. Reads a counterfactual tree and one benchmark JSON of it (no tuning; recorded results only).

    python revealed.py TREE BENCH_JSON
"""
import json
import sys
from pathlib import Path

import cv2
import numpy as np
from PIL import Image

tree, bench = Path(sys.argv[1]), json.load(open(sys.argv[2]))
from sdn3d.data.vkitti1 import intrinsics_for_size

size = tuple(json.load(open(tree / "counterfactual_pairs.json"))["image_size"])
k = intrinsics_for_size(size)
K = np.array([[k.fx, 0, k.cx], [0, k.fy, k.cy], [0, 0, 1]])
pairs = {f"{p['world']}/{p['variation']}/{p['frame']:05d}_{p['instance_id']} delete": p
         for p in json.load(open(tree / "counterfactual_pairs.json"))["pairs"] if p["kind"] == "delete"}
mot = {}
def rows(world, variation):
    key = (world, variation)
    if key not in mot:
        lines = (tree / "vkitti_1.3.1_motgt" / f"{world}_{variation}.txt").read_text().splitlines()
        head = lines[0].split(); mot[key] = [dict(zip(head, ln.split(), strict=False)) for ln in lines[1:]]
    return mot[key]
def hull(r, shape):
    h, w, l = float(r["h3d"]), float(r["w3d"]), float(r["l3d"]); x, y, z, ry = (float(r[k]) for k in ("x3d", "y3d", "z3d", "ry"))
    xs = np.array([1, 1, -1, -1, 1, 1, -1, -1]) * l / 2; zs = np.array([1, -1, -1, 1, 1, -1, -1, 1]) * w / 2; ys = np.array([0, 0, 0, 0, -h, -h, -h, -h])
    c, s = np.cos(ry), np.sin(ry)
    pts = np.stack([c * xs + s * zs + x, ys + y, -s * xs + c * zs + z], 1)
    if (pts[:, 2] < 0.5).any(): return np.zeros(shape, bool)
    uv = (K @ pts.T).T; uv = uv[:, :2] / uv[:, 2:]
    m = np.zeros(shape, np.uint8); cv2.fillConvexPoly(m, cv2.convexHull(uv.astype(np.int32)), 1)
    return m.astype(bool)
out = []
for q in bench["pairs"]:
    if q["kind"] != "delete": continue
    p = pairs[q["key"]]
    vac = np.asarray(Image.open(tree / p["vacated"])) > 0
    tid = p["instance_id"] % 1000 - 1
    rs = [r for r in rows(p["world"], p["variation"]) if int(r["frame"]) == p["frame"]]
    me = [r for r in rs if int(r["tid"]) == tid]
    if not me: continue
    behind = np.zeros_like(vac)
    for r in rs:
        if int(r["tid"]) != tid and float(r["z3d"]) > float(me[0]["z3d"]):
            behind |= hull(r, vac.shape)
    share = float((behind & vac).sum() / max(1, vac.sum()))
    m = q["metrics"]
    out.append((q["key"], share, {f: m[f]["hole"]["psnr"] for f in ("photo:telea", "photo:patchmatch", "photo:rays", "generator") if f in m}))
rng = np.random.default_rng(0)
def ci(d):
    d = np.asarray(d); bt = d[rng.integers(0, len(d), (10000, len(d)))].mean(1)
    return f"{d.mean():+.2f} [{np.percentile(bt, 2.5):+.2f}, {np.percentile(bt, 97.5):+.2f}] {int((d > 0).sum())}/{int((d < 0).sum())}"
print(f"{len(out)} delete pairs; revealed = another car farther than the deleted one covers >= 10 % of the vacated mask (projected 3D box)")
for name, sel in (("reveal a car", [o for o in out if o[1] >= 0.10]), ("reveal none", [o for o in out if o[1] < 0.10])):
    if not sel: print(f"{name}: n=0"); continue
    print(f"{name}: n={len(sel)}, mean revealed share {np.mean([o[1] for o in sel]):.2f}")
    for f in ("photo:telea", "photo:patchmatch", "photo:rays", "generator"):
        if all(f in o[2] for o in sel):
            print(f"  {f:18s} PSNR {np.mean([o[2][f] for o in sel]):.2f}")
    print("  rays - telea:", ci([o[2]["photo:rays"] - o[2]["photo:telea"] for o in sel]))
    best = max(("photo:telea", "photo:patchmatch"), key=lambda f: np.mean([o[2][f] for o in sel]))
    print(f"  rays - best of Telea / PatchMatch here ({best}):", ci([o[2]["photo:rays"] - o[2][best] for o in sel]))
for o in out: print(f"  {o[0]:40s} revealed {o[1]:.2f}  " + " ".join(f"{k.split(':')[-1]} {v:.2f}" for k, v in o[2].items()))
