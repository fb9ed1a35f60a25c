"""fits.py OUT.json SEED...: the fit of the revealed car of every occluder-removed entry (ground truth used only to
diagnose), predicted proposals against ground-truth masks (oracle), main's de-render caches of this helper's t1.sh
(/tmp/s27data/occl40/t1/cache<SEED>: scenes of both rows) and dumps (session 26 del41's runs of main).

Per entry: the revealed car as revealed.py finds it; on each row the scene object that stands for it (predicted: the
proposal not picked for the removal holding most of its seen pixels; oracle: its own id), whether it has geometry,
its fit IoU (``meta['fits']``), its distance and yaw against the ground truth's (``vkitti_1.3.1_motgt``: the object's
``z3d``, ``x3d``, ``ry``; VKITTI ids are ``class * 1000 + tid + 1``); yaw error folded to [0, 90] degrees
(front/back alike) and unfolded [0, 180]. Run with PYTHONPATH=<code>/src /work/main/.venv/bin/python.
"""
import glob
import json
import math
import sys
from pathlib import Path

import numpy as np
import torch

TREES = ("/tmp/s21data/trees/t1_{seed}", "/tmp/s25data/del40/trees/t1_{seed}")
RUNS = "/tmp/s26data/del41/t1/main{seed}_{row}.dump"
CACHE = "/tmp/s27data/occl40/t1/cache{seed}"


def tree_of(seed: str) -> Path:
    for t in TREES:
        if Path(t.format(seed=seed)).is_dir():
            return Path(t.format(seed=seed))
    raise FileNotFoundError(seed)


def motgt(tree: Path, world: str, topic: str, frame: int) -> dict[int, dict]:
    rows = {}
    with open(tree / "vkitti_1.3.1_motgt" / f"{world}_{topic}.txt") as f:
        head = f.readline().split()
        for line in f:
            v = dict(zip(head, line.split(), strict=True))
            if int(v["frame"]) == frame:
                rows[int(v["tid"])] = {"x": float(v["x3d"]), "z": float(v["z3d"]), "ry": float(v["ry"])}
    return rows


def scenes(seed: str) -> dict[tuple[str, str], object]:
    out = {}
    for p in glob.glob(CACHE.format(seed=seed) + "/*.pt"):
        s = torch.load(p, weights_only=False)
        out[(s.meta["source"], s.meta["proposals"])] = s
    return out


def describe(scene, iid: int, truth: dict | None) -> dict:
    ids = scene.objects.instance_id.tolist()
    if iid not in ids:
        return {"object": None}
    k = ids.index(iid)
    fits = {f["id"]: f for f in scene.meta.get("fits", [])}
    out = {"object": iid, "geometry": bool(scene.objects.has_geometry[k]),
           "fit_iou": fits.get(iid, {}).get("fit_iou")}
    if out["geometry"] and truth is not None:
        loc = scene.objects.location[k].tolist()
        ry = float(scene.objects.ry[k])
        d = abs(math.atan2(math.sin(ry - truth["ry"]), math.cos(ry - truth["ry"])))
        out.update({"z": round(loc[2], 2), "z_true": round(truth["z"], 2),
                    "dist_err": round(math.hypot(loc[0] - truth["x"], loc[2] - truth["z"]), 2),
                    "yaw_err": round(math.degrees(d), 1),
                    "yaw_err_folded": round(math.degrees(min(d, math.pi - d)), 1)})
    return out


def main(out: str, seeds: list[str]) -> None:
    rows = []
    for seed in seeds:
        tree, cache = tree_of(seed), scenes(seed)
        for p in sorted(Path(RUNS.format(seed=seed, row="semantic")).glob("*.npz")):
            d = np.load(p)
            if str(d["kind"])[:4] != "occl":
                continue
            reg, src, tgt, prop = d["region"], d["src_inst"], d["tgt_inst"], d["proposals"]
            gt_ids = {int(i) for i in np.atleast_1d(d["gt_ids"])}
            ids, counts = np.unique(tgt[reg], return_counts=True)
            cand = [(c, i) for i, c in zip(ids.tolist(), counts.tolist(), strict=True) if i > 0 and i not in gt_ids]
            if not cand:
                continue
            rid = max(cand)[1]
            seen = src == rid
            if not seen.any():
                continue
            sequence, frames = str(d["key"]).split(" ")
            (world, topic), source = sequence.split("/"), frames.split("->")[0]
            truth = motgt(tree, world, topic, int(source)).get(rid % 1000 - 1)
            picks = {int(i) for i in np.atleast_1d(d["picks"])}
            pid, pc = np.unique(prop[seen], return_counts=True)
            own = sorted(((c, i) for i, c in zip(pid.tolist(), pc.tolist(), strict=True) if i > 0 and i not in picks),
                         reverse=True)
            name = f"vkitti1/{world}/{topic}/{source}"
            row = {"tree": seed, "entry": p.stem, "rid": rid, "seen": int(seen.sum()),
                   "own_share": round(own[0][0] / int(seen.sum()), 3) if own else 0.0}
            pred, oracle = cache.get((name, "semantic")), cache.get((name, "gt"))
            row["predicted"] = describe(pred, own[0][1], truth) if pred is not None and own else {"object": None}
            row["oracle"] = describe(oracle, rid, truth) if oracle is not None else {"object": None}
            rows.append(row)
            print(json.dumps(row))
    tmp = Path(out + ".tmp")
    tmp.write_text(json.dumps(rows, indent=0))
    tmp.replace(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
