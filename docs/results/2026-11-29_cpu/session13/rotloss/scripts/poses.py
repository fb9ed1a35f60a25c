# ruff: noqa: E501, E701, E702
"""poses.py RUN_DIR DUMP_DIR CACHE_DIR TREE OUT.json: per entry of one Table 1 photo run (session 11 semrain's
dbench.py: results.json, per-entry npz, cached source scenes), 3D-SDN minus the 2D paste (PSNR all, objects) and, per
modify operation, the picked object's fitted pose against its ground-truth car (oracle, for scoring only): yaw error
(deg, wrapped), template (fitted / true), distance ratio |c_fit| / |c_true|, length ratio, the operation's turn and
zoom, and the proposal's IoU with its car. Also each entry's per-pixel classes (ana.py's linearised dB shares)."""
import glob
import json
import math
import sys

import numpy as np
import torch

from sdn3d.cli._config import synth_data_source
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.data.sources import read_source
from sdn3d.evaluation.edit_benchmark import index_records

run, dump, cache, tree, out = sys.argv[1:6]
SIZE = (312, 96)
res = json.load(open(f"{run}/results.json"))
entries = load_edit_benchmark(f"{tree}/vkitti_edit_benchmark.json")
records = index_records(read_source(synth_data_source(tree)))
scenes = {}
for f in glob.glob(f"{cache}/*.pt"):
    s = torch.load(f, weights_only=False)
    scenes[(s.meta["source"], s.meta["proposals"])] = s
K = 10 / np.log(10)
DRAWN = (1, 2, 3, 5, 7, 8, 11)


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def row(table, iid):
    hit = (table.instance_id == iid).nonzero().flatten()
    return int(hit[0]) if len(hit) else -1


rows = []
for e in list(res["entries"].values())[0]:
    m = (e.get("metrics") or {}).get("photo") or {}
    if "3d-sdn" not in m or "2d" not in m: continue
    i = e["index"]; entry = entries[i]
    src = records[(entry.world, entry.variation, entry.source_frame)]
    prop = res["config"]["proposals"][0] if isinstance(res["config"].get("proposals"), list) else res["config"].get("proposals")
    scene = scenes.get((src.key, prop))
    z = np.load(f"{dump}/{i:04d}.npz")
    truth = scene_from_frame(src, SIZE)
    d = {"index": i, "key": e["key"], "kind": e["edit_kind"], "weather": entry.variation,
         "d_all": m["3d-sdn"]["all"]["psnr"] - m["2d"]["all"]["psnr"], "d_obj": m["3d-sdn"]["objects"]["psnr"] - m["2d"]["objects"]["psnr"],
         "sdn_all": m["3d-sdn"]["all"]["psnr"], "2d_all": m["2d"]["all"]["psnr"], "ops": []}
    picks, gt_ids = z["picks"].tolist(), z["gt_ids"].tolist()
    for k, op in enumerate(entry.operations):
        o = {"type": op.kind, "turn_deg": math.degrees(op.ry) if op.kind == "modify" else None,
             "zoom": op.zoom if op.kind == "modify" else None}
        if k < len(picks) and k < len(gt_ids) and scene is not None:
            r, t = row(scene.objects, picks[k]), row(truth.objects, gt_ids[k])
            P = z["proposals"] == picks[k]; S = z["src_inst"] == gt_ids[k]
            o["mask_iou"] = float((P & S).sum() / max((P | S).sum(), 1))
            o["truth_px"] = int(S.sum())
            if r >= 0 and t >= 0 and int(scene.objects.template_id[r]) >= 0 and int(truth.objects.template_id[t]) >= 0:
                fo, to = scene.objects, truth.objects
                o["yaw_err"] = math.degrees(wrap(float(fo.ry[r]) - float(to.ry[t])))
                o["tpl"] = (int(fo.template_id[r]), int(to.template_id[t]))
                o["dist_ratio"] = float(fo.location[r].norm() / to.location[t].norm())
                o["len_ratio"] = float(fo.dims[r, 0] / to.dims[t, 0])
                o["true_dist"] = float(to.location[t].norm())
                o["true_alpha"] = math.degrees(wrap(float(to.ry[t]) - math.atan2(float(to.location[t, 0]), float(to.location[t, 2]))))
        d["ops"].append(o)
    # per-pixel classes (ana.py's): T = target shows an edited car, drawn / fill / input by 3D-SDN's source code
    tgt = z["target"].astype(float) / 255; e3 = ((z["sdn"] / 255 - tgt) ** 2).mean(-1); e2 = ((z["d2"] / 255 - tgt) ** 2).mean(-1)
    R = z["region"].astype(bool)
    if z["code"].size and R.sum():
        code = z["code"]; drawn = np.isin(code, DRAWN); fill = code == 4; inp = ~drawn & ~fill
        T = np.isin(z["tgt_inst"], z["gt_ids"]); mse2 = e2[R].mean()
        for name, mm in (("T&drawn", T & drawn), ("~T&drawn", ~T & drawn), ("T&fill", T & fill), ("~T&fill", ~T & fill), ("T&input", T & inp), ("~T&input", ~T & inp)):
            mm = mm & R; d[name] = float(-K * (e3[mm] - e2[mm]).sum() / (R.sum() * mse2))
    rows.append(d)
json.dump(rows, open(out, "w"), indent=1)
rows.sort(key=lambda r: r["d_all"])
tot = sum(r["d_all"] for r in rows if r["d_all"] < 0)
print(f"{run}: n={len(rows)}, mean 3D-2D {np.mean([r['d_all'] for r in rows]):+.3f}; sum of losses {tot:+.2f} dB over {sum(r['d_all'] < 0 for r in rows)} entries")
for r in rows[:20]:
    ops = "; ".join(f"{o['type'][:3]}" + (f" turn {o['turn_deg']:+.0f} zoom {o['zoom']:.2f}" if o['type'] == 'modify' else "") + (f" yawerr {o['yaw_err']:+.0f} tpl {o['tpl'][0]}/{o['tpl'][1]} dist {o['dist_ratio']:.2f} len {o['len_ratio']:.2f} iou {o['mask_iou']:.2f} px {o['truth_px']}" if 'yaw_err' in o else (f" iou {o.get('mask_iou', float('nan')):.2f}" if 'mask_iou' in o else "")) for o in r["ops"])
    cls = " ".join(f"{n}={r.get(n, 0):+.2f}" for n in ("T&drawn", "~T&drawn", "T&fill", "~T&fill", "T&input"))
    print(f"{r['index']:4d} {r['key']:26s} {r['kind']:16s} d={r['d_all']:+.2f} obj={r['d_obj']:+.2f} | {cls}\n      {ops}")
