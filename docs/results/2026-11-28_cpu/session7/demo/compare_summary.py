# ruff: noqa: E402, E501, E701, E702
"""Compare two sdn3d-demo summary.json files figure by figure: the branches' test / validation figures, the test
proposals found, every Table 1 value of the benchmark (latencies aside), the example edit; and the stage times.
Usage: compare_summary.py BEFORE.json AFTER.json [OUT.json]"""
import json
import math
import sys

a, b = (json.load(open(p)) for p in sys.argv[1:3])
rows, out = [], {"figures": [], "differing_bench_values": [], "stages_s": {}}


def same(x, y):
    return x == y or (isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y))


FIGURES = {"semantic": ["test/miou", "test/pq", "val/proposal_recall", "val/proposal_precision", "val/miou"],
           "geometric": ["test/orientation_similarity", "test/mesh_accuracy", "test/reprojection_error_image", "val/reprojection_error_image"],
           "textural": ["test/psnr", "test/l1", "test/obj_psnr", "val/psnr"]}
for branch, keys in FIGURES.items():
    ma, mb = a["training"][branch]["metrics"], b["training"][branch]["metrics"]
    for k in keys:
        out["figures"].append([f"{branch} {k}", ma.get(k), mb.get(k), same(ma.get(k), mb.get(k))])
    out["figures"].append([f"{branch} best checkpoint", a["training"][branch]["best_ckpt"].rsplit("/", 1)[-1], b["training"][branch]["best_ckpt"].rsplit("/", 1)[-1], a["training"][branch]["best_ckpt"].rsplit("/", 1)[-1] == b["training"][branch]["best_ckpt"].rsplit("/", 1)[-1]])
    n_a = sum(1 for k in ma if k.startswith("test/")); diff = [k for k in ma if k.startswith("test/") and not same(ma[k], mb.get(k))]
    out["figures"].append([f"{branch}: all {n_a} test/* figures equal", n_a, n_a - len(diff), not diff])
pa, pb = a["proposal_recall"], b["proposal_recall"]
for k in ("objects", "recall", "precision", "proposals"):
    out["figures"].append([f"test proposals {k}", pa[k], pb[k], same(pa[k], pb[k])])


def walk(x, y, path):
    if isinstance(x, dict) and isinstance(y, dict):
        for k in sorted(set(x) | set(y)):
            if k != "latency_ms":
                walk(x.get(k), y.get(k), f"{path}/{k}")
    elif not same(x, y):
        out["differing_bench_values"].append([path, x, y])


walk(a["bench"]["summary"], b["bench"]["summary"], "bench")
ea, eb = dict(a["edits"]), dict(b["edits"])
for k in ("frame", "car", "edits", "proposals", "recoloured"):
    out["figures"].append([f"edits {k}", ea.get(k), eb.get(k), ea.get(k) == eb.get(k)])
for k in ("data", "train", "bench", "edits"):
    out["stages_s"][k] = [a["stages_s"][k], b["stages_s"][k]]
for br in FIGURES:
    out["stages_s"][f"train {br}"] = [a["training"][br]["demo_wall_s"], b["training"][br]["demo_wall_s"]]
out["stages_s"]["whole demo"] = [a["wall_s"], b["wall_s"]]
out["load"] = [a["machine"].get("load_average_start"), a["machine"].get("load_average_end"), b["machine"].get("load_average_start"), b["machine"].get("load_average_end")]
for name, x, y, ok in out["figures"]:
    print(f"{'same' if ok else 'DIFF'} | {name} | {x} | {y}")
print(f"bench summary values differing (latencies aside): {len(out['differing_bench_values'])}", out["differing_bench_values"][:5])
for k, (x, y) in out["stages_s"].items():
    print(f"stage {k}: {x} -> {y}")
print("load (before start/end, after start/end):", out["load"])
if len(sys.argv) > 3:
    json.dump(out, open(sys.argv[3], "w"), indent=1)
