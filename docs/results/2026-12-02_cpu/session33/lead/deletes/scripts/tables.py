# ruff: noqa: E501
"""tables.py OUTDIR SEED...: Table 1 photo rows of the deletes trees (session 33): 3D-SDN against the 2D paste on
PSNR and L1 of 'all' and 'objects' (a delete's or an occluder removal's 'objects' region is empty: those columns
are left out), per kind (rotate, zoom, move, delete, occluder_removed), per row (semantic = predicted, gt = ground-truth masks
(oracle)), pooled over the trees and per tree, with the floor (floor.py: the unedited source image as the edit).

Intervals: sdn3d.evaluation.paired.paired_difference (its defaults: 95 %, seed 0), resampling groups of entries.
  - "cars, joined" (the verdict's): entries that delete any car in common are one group (connected components over
    the entries' `cars` in results.json: world and ground-truth instance id, so a car deleted from several source
    frames and in both variations is one piece of evidence), the tree's seed in front;
  - "bench": sdn3d.cli.bench.edited_car_groups (entries deleting the same set of cars), beside;
  - "entries": every entry its own, beside.
Entries pooled: those with a finite value for both methods. Writes OUTDIR/tables.md, tables.json and per_entry.jsonl."""
import json
import math
import os
import sys

import numpy as np

from sdn3d.cli.bench import edited_car_groups
from sdn3d.evaluation.paired import paired_difference

OUT = os.environ.get("B", "/tmp/s33/deletes") + "/out"
ROWS = {"semantic": "predicted (semantic proposals)", "gt": "ground-truth masks (oracle)"}
COLS = (("psnr", "all"), ("l1", "all"), ("psnr", "objects"), ("l1", "objects"))


def components(cars_of):  # entry key -> its cars; entries sharing a car joined (union-find)
    parent = {k: k for k in cars_of}

    def find(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k
    owner = {}
    for k, cars in cars_of.items():
        for c in cars:
            if c in owner:
                parent[find(k)] = find(owner[c])
            else:
                owner[c] = k
    return {k: find(k) for k in cars_of}


outdir, seeds = sys.argv[1], sys.argv[2:]
os.makedirs(outdir, exist_ok=True)
entries = []
for seed in seeds:
    floor = {r["index"]: r for r in json.load(open(os.path.join(OUT, f"floor_{seed}.json")))}
    for row in ROWS:
        res = json.load(open(os.path.join(OUT, f"{seed}_{row}", "results.json")))
        (recs,) = res["entries"].values()
        bench_groups = edited_car_groups(recs)
        joined = components({r["index"]: [repr(c) for c in (r.get("cars") or [])] or [f"entry{r['index']}"] for r in recs})
        for r in recs:
            m = (r.get("metrics") or {}).get("photo") or {}
            if not m:
                continue
            vals = {meth: {f"{k}/{g}": m.get(meth, {}).get(g, {}).get(k, float("nan")) for k, g in COLS} for meth in ("3d-sdn", "2d", "2d+")}
            vals["source"] = {f"{k}/{g}": floor[r["index"]]["metrics"][g][k] for k, g in COLS}
            entries.append({"seed": seed, "row": row, "index": r["index"], "key": r.get("key"), "kind": r["edit_kind"],
                            "cars": r.get("cars"), "group_joined": f"{seed}:{joined[r['index']]}",
                            "group_bench": repr((seed,) + tuple(bench_groups[r["index"]])), "values": vals})
with open(os.path.join(outdir, "per_entry.jsonl"), "w") as f:
    for e in entries:
        f.write(json.dumps(e) + "\n")


def fmt(x, k):
    return "-" if not math.isfinite(x) else (f"{x:.2f}" if k == "psnr" else f"{x:.4f}")


def sd(d, k):
    s = "+" if d >= 0 else ""
    return f"{s}{d:.3f}" if k == "psnr" else f"{s}{d:.4f}"


def compare(sel):
    out = {}
    for k, g in COLS:
        c = f"{k}/{g}"
        use = [e for e in sel if all(math.isfinite(e["values"][m][c]) for m in ("3d-sdn", "2d"))]
        if not use:
            continue
        a, b = [e["values"]["3d-sdn"][c] for e in use], [e["values"]["2d"][c] for e in use]
        hib = k == "psnr"
        res = {"n": len(use), "means": {m: float(np.mean([e["values"][m][c] for e in use])) for m in ("3d-sdn", "2d", "2d+", "source")}}
        for name, key in (("joined", "group_joined"), ("bench", "group_bench"), ("entries", None)):
            d = paired_difference(a, b, higher_is_better=hib, groups=None if key is None else [e[key] for e in use])
            res[name] = {**d.to_dict(), "groups": len(set(e[key] for e in use)) if key else len(use)}
        out[c] = res
    return out


results = {}
lines = ["| row | kind | scope | column | n entries (groups joined / bench) | 3D-SDN | 2D | 2D+ | source as edit (floor) | 3D-SDN - 2D [95 % cars, joined] w/l | [95 % bench groups] | [95 % entries] | verdict (joined) |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for row in ROWS:
    for kind in ("rotate", "zoom", "move", "delete", "occluder_removed"):
        for scope in ["pooled"] + seeds:
            sel = [e for e in entries if e["row"] == row and e["kind"] == kind and (scope == "pooled" or e["seed"] == scope)]
            if not sel:
                continue
            res = compare(sel)
            results[f"{row}/{kind}/{scope}"] = res
            for c, r in res.items():
                k = c.split("/")[0]
                j, b, n = r["joined"], r["bench"], r["entries"]
                better = (j["low"] > 0) if k == "psnr" else (j["high"] < 0)
                worse = (j["high"] < 0) if k == "psnr" else (j["low"] > 0)
                verdict = ("too few groups" if j["groups"] < 10 else "3D-SDN better" if better else "2D better" if worse else "no clear difference")
                lines.append(f"| {ROWS[row]} | {kind} | {scope} | {c} | {r['n']} ({j['groups']} / {b['groups']}) | {fmt(r['means']['3d-sdn'], k)} | {fmt(r['means']['2d'], k)} | "
                             f"{fmt(r['means']['2d+'], k)} | {fmt(r['means']['source'], k)} | {sd(j['mean'], k)} [{sd(j['low'], k)}, {sd(j['high'], k)}] {j['wins']}/{j['losses']} | "
                             f"[{sd(b['low'], k)}, {sd(b['high'], k)}] | [{sd(n['low'], k)}, {sd(n['high'], k)}] | {verdict} |")
kinds = {}
for e in entries:
    kinds[(e["row"], e["kind"])] = kinds.get((e["row"], e["kind"]), 0) + 1
open(os.path.join(outdir, "tables.md"), "w").write("\n".join(lines) + "\n\nentries per (row, kind): " + repr(sorted(kinds.items())) + "\n")
json.dump(results, open(os.path.join(outdir, "tables.json"), "w"), indent=1)
print("\n".join(lines))
print(sorted(kinds.items()))
