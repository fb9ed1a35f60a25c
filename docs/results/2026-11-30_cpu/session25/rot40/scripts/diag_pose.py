"""The picked proposal's fitted pose against the oracle's (the same car fitted to its ground-truth mask), per entry.

python diag_pose.py DIAG.json CACHE_PRED CACHE_GT BENCH.json OUT.json   (DIAG.json: diag.py's rows; CACHE_*: dbench.py's
de-render caches of the predicted and the oracle rows (one folder may hold both); BENCH.json: the tree's
vkitti_edit_benchmark.json). Adds yaw_err (degrees, wrapped to [0, 180]), flip (yaw_err > 90), dist_ratio (|c| predicted
/ oracle), len_ratio (the longest side), fit_iou, poor_fit of the predicted fit, and a cause (of the entry's first
operation), the first that holds: wrong pick (proposal IoU with the car < 0.2), class (the proposal's class, Car or
Van, is not the car's), flip (yaw > 90 degrees off), yaw (> 25 degrees), distance/size (distance or length ratio off
by > 15 %), mask (proposal IoU < 0.6), else other."""
import glob
import json
import math
import sys

import torch


def scenes(folder):
    out = {}
    for f in glob.glob(f"{folder}/*.pt"):
        s = torch.load(f, weights_only=False)
        out[(s.meta["source"], s.meta["proposals"])] = s
    return out


def pose(scene, iid):
    t = scene.objects
    hit = (t.instance_id == iid).nonzero()
    if len(hit) == 0:
        return None
    k = int(hit[0])
    fit = next((f for f in scene.meta.get("fits", []) if f["id"] == iid), {})
    return {"loc": t.location[k].tolist(), "ry": float(t.ry[k]), "dims": t.dims[k].tolist(),
            "fit_iou": fit.get("fit_iou"), "poor": fit.get("poor_fit")}


def cause(r):
    if r.get("prop_iou", 0) < 0.2:
        return "wrong pick / proposal off the car"
    if r["pick"] // 1000 != r["gt_id"] // 1000:
        return "class (car / van)"
    if r.get("flip"):
        return "flip"
    if r["yaw_err"] > 25:
        return "yaw"
    if abs(math.log(r["dist_ratio"])) > math.log(1.15) or abs(math.log(r["len_ratio"])) > math.log(1.15):
        return "distance/size"
    if r.get("prop_iou", 1) < 0.6:
        return "mask spill (IoU < 0.6)"
    return "other"


def main():
    rows = json.load(open(sys.argv[1]))
    sp, sg = scenes(sys.argv[2]), scenes(sys.argv[3])
    bench = json.load(open(sys.argv[4]))
    for r in rows:
        e = bench[r["index"]]
        src = f"vkitti1/{e['world']}/{e['topic']}/{e['source']}"
        p = pose(sp[(src, "semantic")], r["pick"]) if (src, "semantic") in sp and r.get("pick", -1) > 0 else None
        g = pose(sg[(src, "gt")], r["gt_id"]) if (src, "gt") in sg else None
        if p is None or g is None:
            r["cause"] = "no pose"
            continue
        d = (p["ry"] - g["ry"] + math.pi) % (2 * math.pi) - math.pi
        r["yaw_err"] = abs(math.degrees(d))
        r["flip"] = r["yaw_err"] > 90
        r["dist_ratio"] = math.dist(p["loc"], [0, 0, 0]) / max(math.dist(g["loc"], [0, 0, 0]), 1e-6)
        r["len_ratio"] = max(p["dims"]) / max(max(g["dims"]), 1e-6)
        r["fit_iou"], r["poor_fit"] = p["fit_iou"], p["poor"]
        r["cause"] = cause(r)
    json.dump(rows, open(sys.argv[5], "w"), indent=1)
    lose = [r for r in rows if r["pred"] < 0 and r.get("oracle", -1) > 0]
    counts = {}
    for r in lose:
        counts[r["cause"]] = counts.get(r["cause"], 0) + 1
    print(f"{len(lose)} predicted-only losses: {counts}")
    for r in sorted(lose, key=lambda r: r["pred"]):
        print(f"#{r['index']:3d} {r['kind'][:4]} {r['pred']:+.2f}/{r['oracle']:+.2f} iou {r.get('prop_iou', 0):.2f} "
              f"yaw {r.get('yaw_err', -1):5.0f} dist {r.get('dist_ratio', 0):.2f} len {r.get('len_ratio', 0):.2f} "
              f"fit {r.get('fit_iou')} poor {r.get('poor_fit')} -> {r['cause']}")


if __name__ == "__main__":
    main()
