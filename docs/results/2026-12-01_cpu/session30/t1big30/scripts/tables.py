# ruff: noqa: E501
"""tables.py OUTDIR SEED...: Table 1 photo rows of main on the held-out trees, 3D-SDN against the 2D paste, per kind,
pooled over the trees and per tree, both rows (semantic = predicted, gt = ground-truth masks (oracle)).

Per (row, kind, scope) and column (PSNR / L1 on 'all' and 'objects'): n (distinct edits), the means of 3D-SDN, 2D,
2D+ and the floor (the unedited source image as the edit: floor.py), 3D-SDN - 2D with the paired bootstrap 95 %
interval of sdn3d.evaluation.paired.paired_difference (4000 resamples, seed 0, groups = sdn3d.cli.bench.
same_edit_groups with the tree's seed in front: entries that are one edit twice are resampled together), 3D-SDN's
wins / losses / ties and the verdict (MIN_ENTRIES = 10 distinct groups). Entries pooled: those where both 3D-SDN and
2D have a finite value (NaN: an empty region, e.g. 'objects' of a delete). Writes OUTDIR/t1_pooled.md, t1_per_tree.md,
t1.json and per_entry.jsonl. Session 30 t1big30. Run with PYTHONPATH=<plain tree>/src."""
import json
import math
import os
import sys

import numpy as np

from sdn3d.cli.bench import same_edit_groups
from sdn3d.data.edit_benchmark import load_edit_benchmark
from sdn3d.evaluation.paired import LOWER_IS_BETTER, paired_difference

T1 = "/tmp/s30/t1big30/t1"
TREES = "/tmp/s30/t1big30/trees"
FLOOR = "/tmp/s30/t1big30/floor"
ROWS = {"semantic": "predicted (semantic proposals)", "gt": "ground-truth masks (oracle)"}
KINDS = ("rotate", "zoom", "delete", "occluder_removed")
COLS = (("psnr", "all"), ("l1", "all"), ("psnr", "objects"), ("l1", "objects"))

outdir, seeds = sys.argv[1], sys.argv[2:]
os.makedirs(outdir, exist_ok=True)
entries = []  # per (seed, row, entry): kind, group, values
for seed in seeds:
    bench = load_edit_benchmark(os.path.join(TREES, f"t1_{seed}", "vkitti_edit_benchmark.json"))
    groups = same_edit_groups(bench)
    floor = {r["index"]: r["metrics"] for r in json.load(open(os.path.join(FLOOR, f"{seed}.json")))}
    for row in ROWS:
        path = os.path.join(T1, f"{seed}_{row}", "results.json")
        if not os.path.exists(path):
            print("missing", path, file=sys.stderr)
            continue
        res = json.load(open(path))
        (recs,) = res["entries"].values()
        for e in recs:
            m = (e.get("metrics") or {}).get("photo") or {}
            if not m:
                continue
            vals = {meth: {f"{k}/{r}": m.get(meth, {}).get(r, {}).get(k, float("nan")) for k, r in COLS}
                    for meth in ("3d-sdn", "2d", "2d+")}
            vals["source"] = {f"{k}/{r}": floor[e["index"]][r][k] for k, r in COLS}
            entries.append({"seed": seed, "row": row, "index": e["index"], "key": e["key"], "kind": e["edit_kind"],
                            "group": repr((seed,) + groups[e["index"]]), "values": vals})

with open(os.path.join(outdir, "per_entry.jsonl"), "w") as f:
    for e in entries:
        f.write(json.dumps(e) + "\n")


def fmt(x, k):
    return "-" if not math.isfinite(x) else (f"{x:.2f}" if k == "psnr" else f"{x:.4f}")


def compare(sel):
    out = {}
    for k, r in COLS:
        c = f"{k}/{r}"
        use = [e for e in sel if all(math.isfinite(e["values"][m][c]) for m in ("3d-sdn", "2d"))]
        if not use:
            continue
        a = [e["values"]["3d-sdn"][c] for e in use]
        b = [e["values"]["2d"][c] for e in use]
        d = paired_difference(a, b, higher_is_better=k not in LOWER_IS_BETTER, groups=[e["group"] for e in use])
        means = {m: float(np.nanmean([e["values"][m][c] for e in use])) for m in ("3d-sdn", "2d", "2d+", "source")}
        out[c] = {"n": d.n, "groups": d.groups, **means, "diff": d.to_dict()}
    return out


def table(title, scopes):
    lines = [f"### {title}", "",
             "| row | scope | kind | column | n (groups) | 3D-SDN | 2D | 2D+ | source as edit (floor) | "
             "3D-SDN - 2D [95 %] | 3D-SDN better / worse / tie | verdict |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    res = {}
    for row in ROWS:
        for scope, sel_seeds in scopes:
            for kind in KINDS + ("all kinds",):
                sel = [e for e in entries if e["row"] == row and e["seed"] in sel_seeds
                       and (kind == "all kinds" or e["kind"] == kind)]
                comp = compare(sel)
                res[f"{row}|{scope}|{kind}"] = comp
                if not comp:
                    lines.append(f"| {row} | {scope} | {kind} | - | 0 | | | | | | | no entries |")
                for c, v in comp.items():
                    k = c.split("/")[0]
                    d = v["diff"]
                    lines.append(
                        f"| {row} | {scope} | {kind} | {k.upper() if k == 'psnr' else 'L1'} {c.split('/')[1]} | "
                        f"{v['n']} ({v['groups']}) | {fmt(v['3d-sdn'], k)} | {fmt(v['2d'], k)} | {fmt(v['2d+'], k)} | "
                        f"{fmt(v['source'], k)} | "
                        + (f"{d['mean']:+.3f} [{d['low']:+.3f}, {d['high']:+.3f}]" if k == "psnr" else
                           f"{d['mean']:+.4f} [{d['low']:+.4f}, {d['high']:+.4f}]")
                        + f" | {d['wins']} / {d['losses']} / {d['ties']} | {d['verdict']} |")
    return lines, res


pooled_lines, pooled = table(f"Pooled over trees {', '.join(seeds)}", [("pooled", set(seeds))])
tree_lines, per_tree = table("Per tree", [(s, {s}) for s in seeds])
verdict = ["### The goal per kind (pooled): 3D-SDN better than 2D on every column the kind has, each interval "
           "excluding 0", "", "| row | kind | columns better / worse / unclear | goal holds |", "|---|---|---|---|"]
for row in ROWS:
    for kind in KINDS + ("all kinds",):
        comp = pooled[f"{row}|pooled|{kind}"]
        vs = [v["diff"]["verdict"] for v in comp.values()]
        verdict.append(f"| {row} | {kind} | {vs.count('better')} / {vs.count('worse')} / "
                       f"{len(vs) - vs.count('better') - vs.count('worse')} | "
                       f"{'yes' if vs and all(v == 'better' for v in vs) else 'no'} |")
with open(os.path.join(outdir, "t1_pooled.md"), "w") as f:
    f.write("\n".join(verdict + [""] + pooled_lines) + "\n")
with open(os.path.join(outdir, "t1_per_tree.md"), "w") as f:
    f.write("\n".join(tree_lines) + "\n")
json.dump({"pooled": pooled, "per_tree": per_tree}, open(os.path.join(outdir, "t1.json"), "w"), indent=1)
print("\n".join(verdict + [""] + pooled_lines))
