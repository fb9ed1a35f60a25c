# ruff: noqa: E402, E501, E701, E702
"""diag.py TREE RUN_DIR CACHE_DIR [SOURCE]: per rotate entry, 3D-SDN minus 2D (PSNR all) and, per modify op, the
picked object's fitted pose against the truth (ground-truth geometry of the source frame): yaw error, flip,
distance error, scale, template, fit record. Sorted by 3D-2D. JSON rows to RUN_DIR.diag.json."""
import json
import math
import os
import sys

import torch

from sdn3d.data.edit_benchmark import load_edit_benchmark, scale_operation
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.vkitti1 import read_frames
from sdn3d.editing.apply import match_objects
from sdn3d.evaluation.edit_benchmark import index_records

tree, run, cache = sys.argv[1:4]
src_name = sys.argv[4] if len(sys.argv) > 4 else None
size = (312, 96)
entries = load_edit_benchmark(os.path.join(tree, "vkitti_edit_benchmark.json"))
records = index_records(read_frames(tree))
res = json.load(open(os.path.join(run, "results.json")))
picks = json.load(open(run + ".picks.json"))
keys = {}
for line in open(os.path.join(cache, "keys.txt")):
    k, f = line.rsplit(" ", 1); keys[k.split("_FitSettings")[0]] = f.strip()
names = [x.name for x in __import__("sdn3d.meshes.templates", fromlist=["x"]).TEMPLATES] if hasattr(__import__("sdn3d.meshes.templates", fromlist=["x"]), "TEMPLATES") else None
rows = []
for src, es in res["entries"].items():
    if src_name and src != src_name: continue
    for e in es:
        if e["edit_kind"] != "rotate": continue
        m = e["metrics"]["photo"]
        if "3d-sdn" not in m: continue
        d = m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"]
        ent = entries[e["index"]]
        rec = records[(ent.world, ent.variation, ent.source_frame)]
        key = [k for k in keys if k.startswith(f"{ent.world}_{ent.variation}_{ent.source_frame}_") and f"_{src}" in k.replace("Proposals.GT", "gt").replace("Proposals.SEMANTIC", "semantic").lower()]
        scene = torch.load(os.path.join(cache, keys[key[0]]), weights_only=False)
        oracle = scene_from_frame(rec, size)
        ops = [scale_operation(op, (1242, 375), size) for op in ent.operations]
        gtids = match_objects(oracle, [op.from_uv for op in ops], [op.kind == "modify" for op in ops])
        pk = picks.get(str(e["index"]), {}).get("picks", {}).get("3d-sdn", [])
        fits = {f["id"]: f for f in scene.meta.get("fits", [])}
        opsd = []
        for j, op in enumerate(ops):
            if op.kind != "modify": continue
            g = gtids[j]; gi = (oracle.objects.instance_id == g).nonzero().flatten()
            p = pk[j] if j < len(pk) else None
            pi = (scene.objects.instance_id == p).nonzero().flatten() if p is not None else torch.zeros(0)
            o = {"op": j, "turn_deg": round(math.degrees(op.ry), 1), "zoom": round(op.zoom, 3), "gt": g, "pick": p}
            if len(gi) and len(pi):
                gi, pi = int(gi[0]), int(pi[0])
                ry_t, ry_f = float(oracle.objects.ry[gi]), float(scene.objects.ry[pi])
                err = abs(math.degrees(math.atan2(math.sin(ry_f - ry_t), math.cos(ry_f - ry_t))))
                zt, zf = float(oracle.objects.location[gi, 2]), float(scene.objects.location[pi, 2])
                mt, mf = oracle.objects.mask[gi], scene.objects.mask[pi]
                iou = float((mt & mf).sum() / max(1, int((mt | mf).sum())))
                o |= {"yaw_err": round(err, 1), "flip": err > 90, "z_true": round(zt, 2), "z_err": round((zf - zt) / zt, 3),
                      "dims_true": [round(x, 2) for x in oracle.objects.dims[gi].tolist()], "dims_fit": [round(x, 2) for x in scene.objects.dims[pi].tolist()],
                      "tpl_true": int(oracle.objects.template_id[gi]), "tpl_fit": int(scene.objects.template_id[pi]),
                      "mask_iou": round(iou, 3), "mask_px": int(mt.sum()), "fit": fits.get(p)}
            opsd.append(o)
        rows.append({"src": src, "index": e["index"], "key": e["key"], "d_all": round(d, 2),
                     "d_obj": round(m["3d-sdn"]["objects"]["psnr"] - m["2d"]["objects"]["psnr"], 2), "psnr3d": round(m["3d-sdn"]["all"]["psnr"], 2), "ops": opsd})
rows.sort(key=lambda r: r["d_all"])
json.dump(rows, open(run + ".diag.json", "w"), indent=1)
for r in rows:
    print(f"{r['src']:9s} #{r['index']:3d} {r['key']:28s} d_all {r['d_all']:+6.2f} d_obj {r['d_obj']:+6.2f}")
    for o in r["ops"]:
        f = o.get("fit") or {}
        print(f"      op{o['op']} turn {o['turn_deg']:+6.1f} zoom {o['zoom']:.2f} yawerr {o.get('yaw_err', '?'):>6} z {o.get('z_true', '?')} zerr {o.get('z_err', '?')} tpl {o.get('tpl_true')}->{o.get('tpl_fit')} dims {o.get('dims_true')}->{o.get('dims_fit')} miou {o.get('mask_iou')} px {o.get('mask_px')} fit {f.get('fit_iou')} {f.get('hypothesis')} {f.get('note') or ''}")
